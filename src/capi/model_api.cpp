// C entry points for models: load, initialise, save, describe.
#include <cmath>
#include <memory>

#include "capi/firewall.h"
#include "capi/handles.h"
#include "runtime/model_file.h"
#include "runtime/model_init.h"

using namespace pleat;
using namespace pleat::capi;

namespace {

uint32_t c_variant(nn::AttentionVariant variant) {
  switch (variant) {
    case nn::AttentionVariant::gat: return PLEAT_VARIANT_GAT;
    case nn::AttentionVariant::lgat: return PLEAT_VARIANT_LGAT;
    case nn::AttentionVariant::flexigat: return PLEAT_VARIANT_FLEXIGAT;
  }
  return 0;
}

nn::AttentionVariant internal_variant(uint32_t variant) {
  switch (variant) {
    case 0:
    case PLEAT_VARIANT_FLEXIGAT: return nn::AttentionVariant::flexigat;
    case PLEAT_VARIANT_GAT: return nn::AttentionVariant::gat;
    case PLEAT_VARIANT_LGAT: return nn::AttentionVariant::lgat;
    default:
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           "'pleat_model_init_options.variant' has unknown value " + std::to_string(variant));
  }
}

}  // namespace

extern "C" {

pleat_status pleat_model_load(const char* path, pleat_model** out_model) {
  return guarded(__func__, [&] {
    require_not_null(path, "path");
    require_not_null(out_model, "out_model");
    *out_model = new pleat_model{runtime::load_model_file(path)};
  });
}

pleat_status pleat_model_initialize(const pleat_body* body, const pleat_model_init_options* options,
                                    pleat_model** out_model) {
  return guarded(__func__, [&] {
    require_not_null(body, "body");
    require_not_null(out_model, "out_model");
    const auto o = read_options(options, "pleat_model_init_options");
    PLEAT_REQUIRE(o.window_frames <= 256, "'pleat_model_init_options.window_frames' " +
                                              std::to_string(o.window_frames) + " is above 256");
    PLEAT_REQUIRE(std::isfinite(o.frame_rate) && o.frame_rate >= 0.0 && o.frame_rate <= 1000.0,
                  "'pleat_model_init_options.frame_rate' must be in (0, 1000] (0 = 30)");
    runtime::ModelInitOptions init;
    init.variant = internal_variant(o.variant);
    if (o.window_frames) init.window_frames = static_cast<int32_t>(o.window_frames);
    if (o.seed) init.seed = o.seed;
    if (o.frame_rate > 0.0) init.frame_rate = o.frame_rate;

    runtime::ModelSkeleton skeleton;
    skeleton.joint_names = body->body.skeleton.names;
    skeleton.parents = body->body.skeleton.parents;
    std::vector<runtime::ShapeEntry> shape;
    for (const ShapeParameter& p : body->body.shape)
      shape.push_back({p.name, static_cast<float>(p.default_value)});
    *out_model = new pleat_model{runtime::initialize_model(skeleton, shape, init)};
  });
}

pleat_status pleat_model_save(const pleat_model* model, const char* path) {
  return guarded(__func__, [&] {
    require_not_null(model, "model");
    require_not_null(path, "path");
    runtime::save_model(*model->model, path);
  });
}

void pleat_model_destroy(pleat_model* model) {
  delete model;
}

pleat_status pleat_model_get_info(const pleat_model* model, pleat_model_info* out_info) {
  return guarded(__func__, [&] {
    require_not_null(model, "model");
    const runtime::Model& m = *model->model;
    pleat_model_info info{};
    info.struct_size = sizeof info;
    info.format_version = runtime::model_format_version(m);
    info.joint_count = static_cast<uint32_t>(m.joint_count());
    info.shape_count = static_cast<uint32_t>(m.shape_count());
    info.window_frames = static_cast<uint32_t>(m.window_frames);
    info.variant = c_variant(m.garment_encoder.layers.front().variant);
    info.default_top_k = static_cast<uint32_t>(m.default_top_k);
    info.code_width = static_cast<uint32_t>(m.code_width());
    info.frame_rate = m.frame_rate;
    info.parameter_count = static_cast<uint64_t>(runtime::parameter_count(m));
    info.offset_filter_length = m.offset_filter_length;
    info.skinning_prior_radius = m.skinning_prior_radius;
    info.skinning_prior_floor = m.skinning_prior_floor;
    write_result(info, out_info, "out_info");
  });
}

const char* pleat_model_joint_name(const pleat_model* model, uint32_t index) {
  if (!model || index >= model->model->skeleton.joint_names.size()) return nullptr;
  return model->model->skeleton.joint_names[index].c_str();
}

}  // extern "C"
