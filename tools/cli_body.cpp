// Loading bodies and motions from command-line options, shared by the
// commands that drive a body (pose, init-model, bake).
#include <sstream>

#include "cli.h"

namespace pleat_cli {
namespace {

// "--shape gender=1,height=0.7": names as pleat_body_shape_name reports them.
void apply_shape(pleat_body* body, const std::string& spec) {
  pleat_body_info info{};
  info.struct_size = sizeof info;
  check(pleat_body_get_info(body, &info), "reading the body");
  std::vector<double> values(info.shape_count);
  check(pleat_body_get_shape(body, values.data(), values.size()), "reading the shape");
  std::stringstream items(spec);
  std::string item;
  while (std::getline(items, item, ',')) {
    const size_t eq = item.find('=');
    if (eq == std::string::npos) throw CliError{"--shape expects name=value pairs, got '" + item + "'", 2};
    const std::string name = item.substr(0, eq);
    uint32_t i = 0;
    while (i < info.shape_count && name != pleat_body_shape_name(body, i)) ++i;
    if (i == info.shape_count) {
      std::string known;
      for (uint32_t k = 0; k < info.shape_count; ++k)
        known += std::string(k ? ", " : "") + pleat_body_shape_name(body, k);
      throw CliError{
          "--shape: unknown entry '" + name + "'; the body has: " + (known.empty() ? "none" : known), 2};
    }
    Args one;
    one.options["v"] = item.substr(eq + 1);
    values[i] = one.number("v", 0.0);
  }
  check(pleat_body_set_shape(body, values.data(), values.size()), "reshaping the body");
}

}  // namespace

BodyPtr load_body(const Args& args) {
  pleat_body_load_options bo{};
  bo.struct_size = sizeof bo;
  const std::string rig = args.get("rig", "cmu_mb");
  if (rig != "cmu_mb" && rig != "default")
    throw CliError{"--rig must be cmu_mb or default, got '" + rig + "'", 2};
  bo.rig = rig == "cmu_mb" ? PLEAT_RIG_CMU_MB : PLEAT_RIG_MAKEHUMAN_DEFAULT;
  pleat_body* b = nullptr;
  check(pleat_body_load(args.get("body").c_str(), &bo, &b), "loading the body '" + args.get("body") + "'");
  BodyPtr body(b, pleat_body_destroy);
  if (args.has("shape")) apply_shape(body.get(), args.get("shape"));
  return body;
}

MotionPtr load_motion_for(const Args& args, const pleat_body* body, double fps) {
  pleat_motion* m = nullptr;
  check(pleat_motion_load(args.get("motion").c_str(), nullptr, &m),
        "loading the motion '" + args.get("motion") + "'");
  MotionPtr source(m, pleat_motion_destroy);
  check(pleat_motion_resample(source.get(), fps, &m), "resampling to " + std::to_string(fps) + " fps");
  MotionPtr resampled(m, pleat_motion_destroy);
  const std::string map = args.get("map");
  check(pleat_motion_retarget(resampled.get(), body, map.empty() ? nullptr : map.c_str(), &m),
        "retargeting onto the body");
  return MotionPtr(m, pleat_motion_destroy);
}

FrameRange frame_range(const Args& args, const pleat_motion* motion, double fps) {
  pleat_motion_info mi{};
  mi.struct_size = sizeof mi;
  check(pleat_motion_get_info(motion, &mi), "reading the motion");
  const size_t first = static_cast<size_t>(args.number("first", 0));
  const size_t available = mi.frame_count > first ? mi.frame_count - first : 0;
  const size_t count = args.has("frames") ? static_cast<size_t>(args.number("frames", 0)) : available;
  if (count == 0 || count > available)
    throw CliError{"frames [" + std::to_string(first) + ", " + std::to_string(first + count) +
                       ") are outside the " + std::to_string(mi.frame_count) + " frames at " +
                       std::to_string(fps) + " fps",
                   2};
  return {first, count, static_cast<size_t>(mi.frame_count)};
}

}  // namespace pleat_cli
