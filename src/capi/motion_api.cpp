// C entry points for motions: BVH and FBX/glTF clips, resampling, retargeting.
#include <algorithm>
#include <cmath>

#include "body/motion_file.h"
#include "body/motion_ops.h"
#include "capi/firewall.h"
#include "capi/handles.h"

using namespace pleat;
using namespace pleat::capi;

pleat_motion::pleat_motion(Motion m, double scale) : motion(std::move(m)), unit_scale(scale) {
  const auto frames = static_cast<size_t>(motion.frame_count);
  const auto joints = static_cast<size_t>(motion.skeleton.joint_count());
  rotations.resize(frames * joints * 4);
  root_positions.resize(frames * 3);
  for (size_t i = 0; i < frames * joints; ++i)
    Eigen::Map<Eigen::Vector4f>(rotations.data() + i * 4) =
        motion.rotations[i].coeffs().cast<float>();  // x y z w
  for (size_t f = 0; f < frames; ++f)
    Eigen::Map<Eigen::RowVector3f>(root_positions.data() + f * 3) =
        motion.root_translation.row(static_cast<Eigen::Index>(f)).cast<float>();
}

namespace {

pleat_motion* load_motion(const std::string& path, const pleat_motion_load_options& o) {
  PLEAT_REQUIRE(std::isfinite(o.unit_scale) && o.unit_scale >= 0.0,
                "'pleat_motion_load_options.unit_scale' must be finite and >= 0");
  MotionFile file = read_motion_file(path, o.unit_scale, o.clip);
  return new pleat_motion{std::move(file.motion), file.unit_scale};
}

}  // namespace

extern "C" {

pleat_status pleat_motion_load(const char* path, const pleat_motion_load_options* options,
                               pleat_motion** out_motion) {
  return guarded(__func__, [&] {
    require_not_null(path, "path");
    require_not_null(out_motion, "out_motion");
    *out_motion = load_motion(path, read_options(options, "pleat_motion_load_options"));
  });
}

void pleat_motion_destroy(pleat_motion* motion) {
  delete motion;
}

pleat_status pleat_motion_get_info(const pleat_motion* motion, pleat_motion_info* out_info) {
  return guarded(__func__, [&] {
    require_not_null(motion, "motion");
    pleat_motion_info info{};
    info.struct_size = sizeof info;
    info.joint_count = static_cast<uint32_t>(motion->motion.skeleton.joint_count());
    info.frame_count = static_cast<uint64_t>(motion->motion.frame_count);
    info.frame_rate = motion->motion.frame_rate;
    info.unit_scale = motion->unit_scale;
    write_result(info, out_info, "out_info");
  });
}

const char* pleat_motion_joint_name(const pleat_motion* motion, uint32_t index) {
  if (!motion || index >= motion->motion.skeleton.names.size()) return nullptr;
  return motion->motion.skeleton.names[index].c_str();
}

pleat_status pleat_motion_resample(const pleat_motion* motion, double frame_rate, pleat_motion** out_motion) {
  return guarded(__func__, [&] {
    require_not_null(motion, "motion");
    require_not_null(out_motion, "out_motion");
    *out_motion = new pleat_motion{resample_motion(motion->motion, frame_rate), motion->unit_scale};
  });
}

pleat_status pleat_motion_retarget(const pleat_motion* motion, const pleat_body* body,
                                   const char* joint_map_path, pleat_motion** out_motion) {
  return guarded(__func__, [&] {
    require_not_null(motion, "motion");
    require_not_null(body, "body");
    require_not_null(out_motion, "out_motion");
    JointMap map;
    RetargetOptions options;
    if (joint_map_path) {
      map = read_joint_map(joint_map_path);
      options.map = &map;
    }
    *out_motion =
        new pleat_motion{retarget_motion(motion->motion, body->body.skeleton, options), motion->unit_scale};
  });
}

pleat_status pleat_motion_get_frames(const pleat_motion* motion, size_t first_frame, size_t frame_count,
                                     float* rotations, size_t rotations_capacity, float* root_positions,
                                     size_t root_capacity) {
  return guarded(__func__, [&] {
    require_not_null(motion, "motion");
    const Motion& m = motion->motion;
    const auto frames = static_cast<size_t>(m.frame_count),
               joints = static_cast<size_t>(m.skeleton.joint_count());
    PLEAT_REQUIRE(first_frame <= frames && frame_count <= frames - first_frame,
                  "frames [" + std::to_string(first_frame) + ", " +
                      std::to_string(first_frame + frame_count) + ") are outside the motion's " +
                      std::to_string(frames));
    if (rotations && rotations_capacity < frame_count * joints * 4)
      fail(PLEAT_ERROR_BUFFER_TOO_SMALL, "rotations_capacity is below frame_count * joint_count * 4 = " +
                                             std::to_string(frame_count * joints * 4));
    if (root_positions && root_capacity < frame_count * 3)
      fail(PLEAT_ERROR_BUFFER_TOO_SMALL,
           "root_capacity is below frame_count * 3 = " + std::to_string(frame_count * 3));
    if (rotations)
      std::copy_n(motion->rotations.data() + first_frame * joints * 4, frame_count * joints * 4, rotations);
    if (root_positions)
      std::copy_n(motion->root_positions.data() + first_frame * 3, frame_count * 3, root_positions);
  });
}

}  // extern "C"
