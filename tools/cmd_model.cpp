// `pleat init-model` and `pleat bake`: a model for a body's skeleton, and a
// garment driven through a model by a motion, written as a point cache.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "cli.h"

namespace pleat_cli {
namespace {

using InstancePtr = std::unique_ptr<pleat_instance, decltype(&pleat_instance_destroy)>;

uint32_t variant_of(const std::string& name) {
  if (name == "flexigat") return PLEAT_VARIANT_FLEXIGAT;
  if (name == "gat") return PLEAT_VARIANT_GAT;
  if (name == "lgat") return PLEAT_VARIANT_LGAT;
  throw CliError{"--variant must be flexigat, gat or lgat, got '" + name + "'", 2};
}

const char* variant_name(uint32_t variant) {
  switch (variant) {
    case PLEAT_VARIANT_GAT: return "gat";
    case PLEAT_VARIANT_LGAT: return "lgat";
    default: return "flexigat";
  }
}

uint32_t count_option(const Args& args, const char* name, double max) {
  const double v = args.number(name, 0.0);
  if (v < 0 || v > max || v != static_cast<double>(static_cast<uint32_t>(v)))
    throw CliError{std::string("--") + name + " expects a whole number in [0, " + std::to_string(max) + "]",
                   2};
  return static_cast<uint32_t>(v);
}

}  // namespace

pleat_model_info model_info(const pleat_model* model) {
  pleat_model_info info{};
  info.struct_size = sizeof info;
  check(pleat_model_get_info(model, &info), "reading the model");
  return info;
}

void print_model_info(const pleat_model* model) {
  const pleat_model_info i = model_info(model);
  std::printf("format version      %u\n", i.format_version);
  std::printf("variant             %s\n", variant_name(i.variant));
  std::printf("joints              %u (%s ... %s)\n", i.joint_count, pleat_model_joint_name(model, 0),
              pleat_model_joint_name(model, i.joint_count - 1));
  std::printf("shape entries       %u\n", i.shape_count);
  std::printf("window              %u frames at %g fps\n", i.window_frames, i.frame_rate);
  std::printf("code width          %u\n", i.code_width);
  std::printf("default top-k       %u\n", i.default_top_k);
  std::printf("parameters          %llu\n", static_cast<unsigned long long>(i.parameter_count));
  if (i.offset_filter_length > 0.0)
    std::printf("offset filter       h = %g cm\n", i.offset_filter_length * 100.0);
  else
    std::printf("offset filter       none\n");
  if (i.skinning_prior_radius > 0.0)
    std::printf("skinning prior      body weights within %g cm, floor %g\n", i.skinning_prior_radius * 100.0,
                i.skinning_prior_floor);
  else
    std::printf("skinning prior      nearest body vertex, floor %g\n", i.skinning_prior_floor);
}

int run_init_model(const Args& args) {
  if (!args.has("body") || !args.has("output"))
    throw CliError{"needs --body (the skeleton the model drives) and -o model.pleat", 2};
  BodyPtr body = load_body(args);
  pleat_model_init_options o{};
  o.struct_size = sizeof o;
  o.variant = variant_of(args.get("variant", "flexigat"));
  o.window_frames = count_option(args, "window", 256);
  o.seed = static_cast<uint64_t>(count_option(args, "seed", 4294967295.0));
  o.frame_rate = args.number("fps", 30.0);
  pleat_model* m = nullptr;
  check(pleat_model_initialize(body.get(), &o, &m), "initialising the model");
  ModelPtr model(m, pleat_model_destroy);
  check(pleat_model_save(model.get(), args.get("output").c_str()), "writing '" + args.get("output") + "'");
  print_model_info(model.get());
  std::printf("wrote %s\n", args.get("output").c_str());
  return 0;
}

GarmentPtr load_garment(const std::string& path, double unit_scale) {
  pleat_garment_load_options go{};
  go.struct_size = sizeof go;
  go.unit_scale = unit_scale;
  pleat_garment* g = nullptr;
  check(pleat_garment_load(path.c_str(), &go, &g), "loading the garment '" + path + "'");
  return GarmentPtr(g, pleat_garment_destroy);
}

uint32_t stage_of(const std::string& name) {
  if (name == "full") return PLEAT_STAGE_FULL;
  if (name == "skinning") return PLEAT_STAGE_SKINNING;
  if (name == "blend-shapes") return PLEAT_STAGE_BLEND_SHAPES;
  throw CliError{"stage must be skinning, blend-shapes or full, got '" + name + "'", 2};
}

std::vector<float> bake_frames(const pleat_model* model, const pleat_garment* garment, const pleat_body* body,
                               const pleat_motion* motion, const FrameRange& range,
                               const BakeSettings& settings, const std::function<void(size_t)>& progress) {
  pleat_instance_options io{};
  io.struct_size = sizeof io;
  io.threads = settings.threads;
  io.top_k = settings.top_k;
  io.max_batch = 16;
  pleat_instance* in = nullptr;
  check(pleat_instance_create(model, garment, body, &io, &in), "binding the model");
  InstancePtr instance(in, pleat_instance_destroy);
  pleat_instance_info ii{};
  ii.struct_size = sizeof ii;
  check(pleat_instance_get_info(instance.get(), &ii), "reading the instance");

  const size_t n = ii.vertex_count;
  pleat_evaluate_options eo{};
  eo.struct_size = sizeof eo;
  eo.stage = settings.stage;
  eo.body_collision_distance = settings.body_collision;
  std::vector<float> positions(range.count * n * 3);
  const size_t chunk = 64;
  for (size_t f = 0; f < range.count; f += chunk) {
    const size_t c = std::min(chunk, range.count - f);
    pleat_evaluate_outputs out{};
    out.struct_size = sizeof out;
    out.positions = {positions.data() + f * n * 3, 0};
    // Frames before range.first are the history the motion window and the
    // velocities look at; the motion holds them all.
    check(pleat_instance_evaluate_motion(instance.get(), motion, range.first + f, c, &eo, &out),
          "evaluating frames");
    progress(f + c);
  }
  return positions;
}

int run_bake(const Args& args) {
  for (const char* needed : {"model", "garment", "body", "motion", "output"})
    if (!args.has(needed))
      throw CliError{
          "needs --model, --garment, --body, --motion and -o out.pc2|out.mdd|out.glb|out.usda|frame_####.obj",
          2};
  pleat_model* m = nullptr;
  check(pleat_model_load(args.get("model").c_str(), &m), "loading the model '" + args.get("model") + "'");
  ModelPtr model(m, pleat_model_destroy);
  const pleat_model_info mi = model_info(model.get());
  GarmentPtr garment = load_garment(args.get("garment"), args.number("unit-scale", 0.0));
  BodyPtr body = load_body(args);
  MotionPtr motion = load_motion_for(args, body.get(), mi.frame_rate);
  const FrameRange range = frame_range(args, motion.get(), mi.frame_rate);

  BakeSettings settings;
  settings.stage = stage_of(args.get("stage", "full"));
  settings.threads = count_option(args, "threads", 256);
  settings.top_k = count_option(args, "top-k", 1 << 20);
  settings.body_collision = static_cast<float>(args.number("body-collision", 0.0));
  const std::vector<float> positions =
      bake_frames(model.get(), garment.get(), body.get(), motion.get(), range, settings,
                  [&](size_t done) { std::fprintf(stderr, "\rbaked %zu / %zu frames", done, range.count); });
  std::fprintf(stderr, "\n");
  const size_t n = positions.size() / (3 * range.count);
  check(pleat_cache_write(args.get("output").c_str(), PLEAT_CACHE_AUTO, garment.get(), {positions.data(), 0},
                          range.count, n, mi.frame_rate),
        "writing '" + args.get("output") + "'");
  std::printf("wrote %s: %zu frames of %zu vertices at %g fps\n", args.get("output").c_str(), range.count, n,
              mi.frame_rate);
  return 0;
}

}  // namespace pleat_cli
