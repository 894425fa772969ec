// `pleat pose`: a body driven by a motion, written as a PC2 cache (+ rest OBJ).
#include <cstdio>
#include <memory>
#include <sstream>
#include <vector>

#include "cli.h"

namespace pleat_cli {
namespace {

using BodyPtr = std::unique_ptr<pleat_body, decltype(&pleat_body_destroy)>;
using MotionPtr = std::unique_ptr<pleat_motion, decltype(&pleat_motion_destroy)>;

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

int run_pose(const Args& args) {
  if (!args.has("body") || !args.has("motion") || !args.has("output"))
    throw CliError{"needs --body, --motion and -o out.pc2", 2};
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

  pleat_motion* m = nullptr;
  check(pleat_motion_load(args.get("motion").c_str(), nullptr, &m),
        "loading the motion '" + args.get("motion") + "'");
  MotionPtr source(m, pleat_motion_destroy);
  const double fps = args.number("fps", 30.0);
  check(pleat_motion_resample(source.get(), fps, &m), "resampling to " + std::to_string(fps) + " fps");
  MotionPtr resampled(m, pleat_motion_destroy);
  const std::string map = args.get("map");
  check(pleat_motion_retarget(resampled.get(), body.get(), map.empty() ? nullptr : map.c_str(), &m),
        "retargeting onto the body");
  MotionPtr motion(m, pleat_motion_destroy);

  pleat_body_info info{};
  info.struct_size = sizeof info;
  check(pleat_body_get_info(body.get(), &info), "reading the body");
  pleat_motion_info mi{};
  mi.struct_size = sizeof mi;
  check(pleat_motion_get_info(motion.get(), &mi), "reading the motion");
  const size_t first = static_cast<size_t>(args.number("first", 0));
  const size_t available = mi.frame_count > first ? mi.frame_count - first : 0;
  const size_t count = args.has("frames") ? static_cast<size_t>(args.number("frames", 0)) : available;
  if (count == 0 || count > available)
    throw CliError{"frames [" + std::to_string(first) + ", " + std::to_string(first + count) +
                       ") are outside the " + std::to_string(mi.frame_count) + " frames at " +
                       std::to_string(fps) + " fps",
                   2};

  const size_t n = info.vertex_count;
  std::vector<float> frames(count * n * 3);
  const size_t chunk = 32;
  for (size_t f = 0; f < count; f += chunk) {
    const size_t c = std::min(chunk, count - f);
    check(pleat_body_pose_motion(body.get(), motion.get(), first + f, c, {frames.data() + f * n * 3, 0}),
          "posing frames");
    std::fprintf(stderr, "\rposed %zu / %zu frames", f + c, count);
  }
  std::fprintf(stderr, "\n");
  check(pleat_cache_write(args.get("output").c_str(), PLEAT_CACHE_AUTO, nullptr, {frames.data(), 0}, count, n,
                          fps),
        "writing '" + args.get("output") + "'");
  std::printf("wrote %s: %zu frames of %zu vertices at %g fps\n", args.get("output").c_str(), count, n, fps);

  if (args.has("rest-obj")) {
    std::vector<float> rest(n * 3);
    std::vector<uint32_t> triangles(info.triangle_count * size_t{3});
    check(pleat_body_get_rest(body.get(), rest.data(), rest.size(), triangles.data(), triangles.size(),
                              nullptr, 0),
          "reading the rest body");
    check(pleat_mesh_write_obj(args.get("rest-obj").c_str(), rest.data(), n, triangles.data(),
                               info.triangle_count),
          "writing '" + args.get("rest-obj") + "'");
    std::printf("wrote %s\n", args.get("rest-obj").c_str());
  }
  return 0;
}

}  // namespace pleat_cli
