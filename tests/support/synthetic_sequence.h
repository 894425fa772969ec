#pragma once
// A small synthetic training sequence in the on-disk format (io/sequence.h)
// for the trainer's tests: the MakeHuman body walks (the CMU fixture clip);
// the "simulated" skirt is the body's own skinning of a skirt pushed 2 cm
// outwards, an offset the untrained model does not know.
#include <cmath>
#include <string>
#include <vector>

#include "body/bvh.h"
#include "body/makehuman.h"
#include "body/motion_ops.h"
#include "capi/pleat.h"
#include "core/nearest_points.h"
#include "io/sequence.h"
#include "support/test_support.h"

namespace pleat_test {

using namespace pleat;

// An open cylinder of rings x segments vertices around the hips.
inline pleat::TriMesh skirt(double hip_height) {
  const int rings = 5, segments = 16;
  TriMesh m;
  m.vertices.resize(rings * segments, 3);
  const double pi = std::acos(-1.0);
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * pi * s / segments, y = hip_height + 0.05 - 0.3 * r / (rings - 1);
      const double radius = 0.2 + 0.06 * r / (rings - 1);
      m.vertices.row(r * segments + s) << radius * std::sin(a), y, radius * std::cos(a) + 0.01;
    }
  m.triangles.resize((rings - 1) * segments * 2, 3);
  int k = 0;
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      m.triangles.row(k++) << a, a + segments, b;
      m.triangles.row(k++) << b, a + segments, b + segments;
    }
  return m;
}

// Writes one 31-frame sequence into root/<name> and returns that folder; the
// skirt is pushed `push` metres outwards.
inline std::string write_skirt_walk(const std::string& root, double push = 0.02,
                                    const std::string& name = "skirt_walk") {
  const std::string body_dir = pleat_test::asset_dir() + "/body";
  const Body body = MakeHumanModel::load(body_dir)->body(makehuman_default_beta());
  const Motion walk = retarget_motion(
      resample_motion(read_bvh(pleat_test::source_dir() + "/tests/fixtures/motion/12_03_walk_121.bvh").motion,
                      30.0),
      body.skeleton);
  const TriMesh rest = skirt(body.skeleton.rest_translation(0, 1));
  // Ground truth: the skirt pushed 2 cm outwards, skinned with the weights of
  // the nearest body vertex (what the model's skinning prior starts from).
  Points3d pushed = rest.vertices;
  for (Eigen::Index v = 0; v < pushed.rows(); ++v) {
    Eigen::Vector3d radial(pushed(v, 0), 0, pushed(v, 2) - 0.01);
    pushed.row(v) += push * radial.normalized().transpose();
  }
  const std::vector<int32_t> nearest = nearest_points(body.rest.vertices, rest.vertices);
  SkinWeights weights;
  weights.joint_count = body.joint_count();
  for (int32_t b : nearest) {
    for (int32_t k = body.weights.offsets[b]; k < body.weights.offsets[b + 1]; ++k) {
      weights.joints.push_back(body.weights.joints[k]);
      weights.weights.push_back(body.weights.weights[k]);
    }
    weights.offsets.push_back(static_cast<int32_t>(weights.joints.size()));
  }
  SequenceData d;
  d.meta.frame_rate = 30.0;
  d.meta.frame_count = walk.frame_count;
  d.meta.garment_name = "skirt";
  d.meta.garment_source = "synthetic";
  d.meta.body_source = body_dir;
  d.meta.body_kind = PLEAT_BODY_MAKEHUMAN;
  d.meta.body_rig = PLEAT_RIG_CMU_MB;
  d.meta.motion_source = "12_03_walk_121.bvh";
  d.meta.joint_names = body.skeleton.names;
  d.meta.simulator_json = R"({"name": "synthetic: pushed skirt, body skinning"})";
  d.garment_rest = rest;
  SkinningWorkspace ws;
  d.garment_frames.resize(static_cast<size_t>(walk.frame_count * rest.vertex_count() * 3));
  const Points3f pushed_f = pushed.cast<float>();
  skin_frames(pushed_f, weights, walk, 0, walk.frame_count, &ws, d.garment_frames.data(),
              d.garment_frames.size());
  const Points3d posed = pose_body_frames(body, walk, 0, walk.frame_count);
  d.body_frames.assign(posed.data(), posed.data() + posed.size());
  for (int64_t f = 0; f < walk.frame_count; ++f) {
    for (int32_t j = 0; j < body.joint_count(); ++j) {
      const Eigen::Quaterniond& q = walk.frame(f)[j];
      d.rotations.insert(d.rotations.end(), {float(q.x()), float(q.y()), float(q.z()), float(q.w())});
    }
    for (int k = 0; k < 3; ++k) d.root_positions.push_back(float(walk.root_translation(f, k)));
  }
  const std::string dir = root + "/" + name;
  write_sequence(dir, d);
  return dir;
}

}  // namespace pleat_test
