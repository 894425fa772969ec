// C entry points for instances: bind a model to a garment and a body, then
// evaluate frames into caller buffers.
#include <algorithm>
#include <limits>

#include "capi/firewall.h"
#include "capi/frames.h"
#include "capi/handles.h"

using namespace pleat;
using namespace pleat::capi;

namespace {

int32_t checked_count(uint32_t value, uint32_t limit, const char* field) {
  PLEAT_REQUIRE(value <= limit, std::string("'") + field + "' " + std::to_string(value) + " is above " +
                                    std::to_string(limit));
  return static_cast<int32_t>(value);
}

runtime::InstanceOptions instance_options(const pleat_instance_options* options) {
  const auto o = read_options(options, "pleat_instance_options");
  runtime::InstanceOptions result;
  if (o.threads) result.threads = checked_count(o.threads, 256, "pleat_instance_options.threads");
  result.top_k = checked_count(o.top_k, 1u << 20, "pleat_instance_options.top_k");
  if (o.max_batch) result.max_batch = checked_count(o.max_batch, 4096, "pleat_instance_options.max_batch");
  return result;
}

runtime::Stage stage_of(const pleat_evaluate_options& o) {
  switch (o.stage) {
    case PLEAT_STAGE_FULL:
    case PLEAT_STAGE_REFINEMENT: return runtime::Stage::refinement;
    case PLEAT_STAGE_SKINNING: return runtime::Stage::skinning;
    case PLEAT_STAGE_BLEND_SHAPES: return runtime::Stage::blend_shapes;
    default:
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           "'pleat_evaluate_options.stage' has unknown value " + std::to_string(o.stage));
  }
}

runtime::OutputBuffer output(pleat_frames frames, const char* name, size_t floats_per_frame) {
  if (!frames.data) return {};
  if (frames.frame_stride == 0) return {frames.data, floats_per_frame};
  PLEAT_REQUIRE(frames.frame_stride >= floats_per_frame,
                std::string("'pleat_evaluate_outputs.") + name + ".frame_stride' " +
                    std::to_string(frames.frame_stride) + " is below the " +
                    std::to_string(floats_per_frame) + " floats of a frame");
  return {frames.data, frames.frame_stride};
}

// Frames [first, first + count) of `poses` into the caller's outputs.
void evaluate(runtime::Instance& in, const runtime::PoseSequence& poses, size_t first, size_t count,
              const pleat_evaluate_options* options, const pleat_evaluate_outputs* outputs) {
  const auto o = read_options(outputs, "pleat_evaluate_outputs");
  const size_t n = static_cast<size_t>(in.vertex_count());
  runtime::EvaluateOutputs out;
  out.positions = output(o.positions, "positions", n * 3);
  out.normals = output(o.normals, "normals", n * 3);
  out.skinning_weights =
      output(o.skinning_weights, "skinning_weights", n * static_cast<size_t>(in.model().joint_count()));
  out.low = output(o.low, "low", n * 3);
  out.mid = output(o.mid, "mid", n * 3);
  out.high = output(o.high, "high", n * 3);
  const auto settings = read_options(options, "pleat_evaluate_options");
  runtime::EvaluateDetail detail;
  detail.interval = std::max(
      checked_count(settings.refinement_interval, 1u << 20, "pleat_evaluate_options.refinement_interval"), 1);
  const char* band_names[3] = {"low", "mid", "high"};
  for (int b = 0; b < 3; ++b) {
    const float a = settings.band_attenuation[b];
    PLEAT_REQUIRE(a >= 0.0f && a <= 1.0f, std::string("'pleat_evaluate_options.band_attenuation[") +
                                              std::to_string(b) + "]' (" + band_names[b] + ") is " +
                                              std::to_string(a) + ", expected 0..1");
    detail.band_attenuation[b] = a;
  }
  PLEAT_REQUIRE(settings.body_collision_distance >= 0.0f && settings.body_collision_distance <= 1.0f,
                "'pleat_evaluate_options.body_collision_distance' is " +
                    std::to_string(settings.body_collision_distance) + " m, expected 0..1");
  detail.body_collision = settings.body_collision_distance;
  in.evaluate(poses, static_cast<int64_t>(first), static_cast<int64_t>(count), stage_of(settings), out,
              detail);
}

}  // namespace

extern "C" {

pleat_status pleat_instance_create(const pleat_model* model, const pleat_garment* garment,
                                   const pleat_body* body, const pleat_instance_options* options,
                                   pleat_instance** out_instance) {
  return guarded(__func__, [&] {
    require_not_null(model, "model");
    require_not_null(garment, "garment");
    require_not_null(body, "body");
    require_not_null(out_instance, "out_instance");
    *out_instance = new pleat_instance{
        runtime::Instance(model->model, garment->garment, body->body, instance_options(options)),
        body->body.skeleton.names};
  });
}

void pleat_instance_destroy(pleat_instance* instance) {
  delete instance;
}

pleat_status pleat_instance_get_info(const pleat_instance* instance, pleat_instance_info* out_info) {
  return guarded(__func__, [&] {
    require_not_null(instance, "instance");
    const runtime::Instance& in = instance->instance;
    pleat_instance_info info{};
    info.struct_size = sizeof info;
    info.vertex_count = static_cast<uint32_t>(in.vertex_count());
    info.joint_count = static_cast<uint32_t>(in.joint_count());
    info.top_k = static_cast<uint32_t>(in.top_k());
    info.window_frames = static_cast<uint32_t>(in.model().window_frames);
    info.max_batch = static_cast<uint32_t>(in.max_batch());
    info.frame_rate = in.model().frame_rate;
    write_result(info, out_info, "out_info");
  });
}

pleat_status pleat_instance_evaluate(pleat_instance* instance, const pleat_poses* poses, size_t first_frame,
                                     size_t frame_count, const pleat_evaluate_options* options,
                                     const pleat_evaluate_outputs* outputs) {
  return guarded(__func__, [&] {
    require_not_null(instance, "instance");
    require_not_null(poses, "poses");
    require_not_null(outputs, "outputs");
    runtime::Instance& in = instance->instance;
    const auto p = read_options(poses, "pleat_poses");
    PLEAT_REQUIRE(p.frame_count <= static_cast<size_t>(std::numeric_limits<int64_t>::max()) &&
                      first_frame <= p.frame_count && frame_count <= p.frame_count - first_frame,
                  "frames [" + std::to_string(first_frame) + ", " +
                      std::to_string(first_frame + frame_count) + ") are outside the " +
                      std::to_string(p.frame_count) + " frames of 'poses'");
    PLEAT_REQUIRE(p.frame_count == 0 || (p.rotations && p.root_positions),
                  "'pleat_poses.rotations' and 'pleat_poses.root_positions' must not be NULL");
    runtime::PoseSequence sequence;
    sequence.rotations = p.rotations;
    sequence.root_positions = p.root_positions;
    sequence.frame_count = static_cast<int64_t>(p.frame_count);
    sequence.joint_count = static_cast<int32_t>(p.joint_count);
    sequence.frame_rate = p.frame_rate;
    evaluate(in, sequence, first_frame, frame_count, options, outputs);
  });
}

pleat_status pleat_instance_set_vertex_mask(pleat_instance* instance, const uint8_t* mask,
                                            size_t vertex_count) {
  return guarded(__func__, [&] {
    require_not_null(instance, "instance");
    runtime::Instance& in = instance->instance;
    if (mask)
      PLEAT_REQUIRE(vertex_count == static_cast<size_t>(in.vertex_count()),
                    "'vertex_count' is " + std::to_string(vertex_count) + ", the instance's garment has " +
                        std::to_string(in.vertex_count()) + " vertices");
    in.set_vertex_mask(mask);
  });
}

pleat_status pleat_instance_evaluate_motion(pleat_instance* instance, const pleat_motion* motion,
                                            size_t first_frame, size_t frame_count,
                                            const pleat_evaluate_options* options,
                                            const pleat_evaluate_outputs* outputs) {
  return guarded(__func__, [&] {
    require_not_null(instance, "instance");
    require_not_null(motion, "motion");
    require_not_null(outputs, "outputs");
    const Motion& m = motion->motion;
    const std::vector<std::string>& body = instance->body_joints;
    // Messages are built only on failure: a valid call allocates nothing.
    if (m.skeleton.names.size() != body.size())
      fail(PLEAT_ERROR_INVALID_ARGUMENT, "the motion has " + std::to_string(m.skeleton.names.size()) +
                                             " joints, the bound body " + std::to_string(body.size()) +
                                             ": retarget it onto the body (pleat_motion_retarget)");
    for (size_t j = 0; j < body.size(); ++j)
      if (m.skeleton.names[j] != body[j])
        fail(PLEAT_ERROR_INVALID_ARGUMENT,
             "motion joint " + std::to_string(j) + " is '" + m.skeleton.names[j] +
                 "', the bound body's is '" + body[j] +
                 "': retarget the motion onto the body (pleat_motion_retarget)");
    const auto frames = static_cast<size_t>(m.frame_count);
    if (first_frame > frames || frame_count > frames - first_frame)
      fail(PLEAT_ERROR_INVALID_ARGUMENT, "frames [" + std::to_string(first_frame) + ", " +
                                             std::to_string(first_frame + frame_count) +
                                             ") are outside the motion's " + std::to_string(frames));
    runtime::PoseSequence sequence;
    sequence.rotations = motion->rotations.data();
    sequence.root_positions = motion->root_positions.data();
    sequence.frame_count = m.frame_count;
    sequence.joint_count = m.skeleton.joint_count();
    sequence.frame_rate = m.frame_rate;
    evaluate(instance->instance, sequence, first_frame, frame_count, options, outputs);
  });
}

}  // extern "C"
