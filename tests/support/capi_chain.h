#pragma once
// For C API tests of models and instances: a three-joint chain body
// (hips -> spine -> arm) skinning a small strip, a grid garment in front of
// it, an initialised model, and frames of poses to evaluate.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "capi/pleat.h"
#include "support/capi_support.h"

namespace pleat_test::chain {

using BodyPtr = std::unique_ptr<pleat_body, decltype(&pleat_body_destroy)>;
using ModelPtr = std::unique_ptr<pleat_model, decltype(&pleat_model_destroy)>;
using InstancePtr = std::unique_ptr<pleat_instance, decltype(&pleat_instance_destroy)>;

constexpr uint32_t kJoints = 3;
const float kJointPositions[kJoints * 3] = {0.0f, 1.0f, 0.0f, 0.0f, 1.3f, 0.0f, 0.3f, 1.4f, 0.0f};

// A three-joint chain (hips -> spine -> arm) skinning a small quad strip.
inline BodyPtr chain_body(const char* arm_name = "arm") {
  const char* names[kJoints] = {"hips", "spine", arm_name};
  const int32_t parents[kJoints] = {-1, 0, 1};
  const pleat_test::SimpleMesh mesh = pleat_test::grid(3, 4, 0.2f, Eigen::Vector3f(-0.2f, 0.8f, 0.1f));
  std::vector<uint32_t> joints;
  std::vector<float> weights;
  for (size_t v = 0; v < mesh.vertex_count(); ++v) {
    const float y = mesh.positions[v * 3 + 1];
    const float upper = std::min(1.0f, std::max(0.0f, (y - 0.9f) / 0.4f));
    joints.insert(joints.end(), {0u, 1u});
    weights.insert(weights.end(), {1.0f - upper, upper});
  }
  pleat_body_desc d{};
  d.struct_size = sizeof d;
  d.joint_count = kJoints;
  d.joint_names = names;
  d.parents = parents;
  d.joint_positions = kJointPositions;
  d.vertex_count = mesh.vertex_count();
  d.positions = mesh.positions.data();
  d.triangle_count = mesh.triangle_count();
  d.triangles = mesh.triangles.data();
  d.influences = 2;
  d.weight_joints = joints.data();
  d.weights = weights.data();
  pleat_body* b = nullptr;
  EXPECT_EQ(pleat_body_create(&d, &b), PLEAT_OK) << pleat_last_error();
  return BodyPtr(b, pleat_body_destroy);
}

// A garment around the chain: a 5 x 6 grid in front of the body.
inline pleat_test::SimpleMesh garment_mesh() {
  return pleat_test::grid(5, 6, 0.1f, Eigen::Vector3f(-0.2f, 0.8f, 0.15f));
}

inline ModelPtr initialised(const pleat_body* body, uint32_t variant = 0, uint32_t window = 0,
                            double fps = 0) {
  pleat_model_init_options o{};
  o.struct_size = sizeof o;
  o.variant = variant;
  o.window_frames = window;
  o.frame_rate = fps;
  o.seed = 7;
  pleat_model* m = nullptr;
  EXPECT_EQ(pleat_model_initialize(body, &o, &m), PLEAT_OK) << pleat_last_error();
  return ModelPtr(m, pleat_model_destroy);
}

inline pleat_model_info info_of(const pleat_model* model) {
  pleat_model_info info{};
  info.struct_size = sizeof info;
  EXPECT_EQ(pleat_model_get_info(model, &info), PLEAT_OK) << pleat_last_error();
  return info;
}

inline InstancePtr bind(const pleat_model* model, const pleat_garment* garment, const pleat_body* body,
                        uint32_t threads = 0, uint32_t max_batch = 0) {
  pleat_instance_options o{};
  o.struct_size = sizeof o;
  o.threads = threads;
  o.max_batch = max_batch;
  pleat_instance* in = nullptr;
  EXPECT_EQ(pleat_instance_create(model, garment, body, &o, &in), PLEAT_OK) << pleat_last_error();
  return InstancePtr(in, pleat_instance_destroy);
}

// Frames of poses: every joint rotation is `rotation` (x, y, z, w) for the
// root and identity for the others; the root moves by `step` per frame.
struct Poses {
  std::vector<float> rotations, roots;
  pleat_poses view(double fps = 30.0) const {
    pleat_poses p{};
    p.struct_size = sizeof p;
    p.joint_count = kJoints;
    p.frame_count = roots.size() / 3;
    p.rotations = rotations.data();
    p.root_positions = roots.data();
    p.frame_rate = fps;
    return p;
  }
};

inline Poses root_motion(size_t frames, const float step[3], const float root_rotation[4]) {
  Poses p;
  for (size_t f = 0; f < frames; ++f) {
    for (uint32_t j = 0; j < kJoints; ++j) {
      if (j == 0)
        p.rotations.insert(p.rotations.end(), root_rotation, root_rotation + 4);
      else
        p.rotations.insert(p.rotations.end(), {0.0f, 0.0f, 0.0f, 1.0f});
    }
    for (int k = 0; k < 3; ++k) p.roots.push_back(kJointPositions[k] + step[k] * static_cast<float>(f));
  }
  return p;
}

inline pleat_evaluate_options stage_options(uint32_t stage) {
  pleat_evaluate_options o{};
  o.struct_size = sizeof o;
  o.stage = stage;
  return o;
}

// Outputs with positions only, packed, into `positions`.
inline pleat_evaluate_outputs positions_into(float* positions) {
  pleat_evaluate_outputs out{};
  out.struct_size = sizeof out;
  out.positions = {positions, 0};
  return out;
}

inline std::vector<float> evaluate(pleat_instance* instance, const Poses& poses, size_t first, size_t count,
                                   uint32_t stage, std::vector<float>* weights = nullptr) {
  pleat_instance_info info{};
  info.struct_size = sizeof info;
  EXPECT_EQ(pleat_instance_get_info(instance, &info), PLEAT_OK);
  std::vector<float> positions(count * info.vertex_count * 3, -1.0f);
  const pleat_evaluate_options o = stage_options(stage);
  pleat_evaluate_outputs out = positions_into(positions.data());
  if (weights) {
    weights->assign(count * info.vertex_count * kJoints, -1.0f);
    out.skinning_weights = {weights->data(), 0};
  }
  const pleat_poses p = poses.view();
  EXPECT_EQ(pleat_instance_evaluate(instance, &p, first, count, &o, &out), PLEAT_OK) << pleat_last_error();
  return positions;
}

const float kIdentity[4] = {0.0f, 0.0f, 0.0f, 1.0f};
const float kStill[3] = {0.0f, 0.0f, 0.0f};

}  // namespace pleat_test::chain
