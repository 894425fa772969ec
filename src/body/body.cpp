#include "body/body.h"

#include <cmath>

#include "core/error.h"
#include "core/nearest_points.h"

namespace pleat {
namespace {

void check_rotations(const Eigen::Quaterniond* rotations, int32_t n, const Skeleton& s,
                     const std::string& where) {
  for (int32_t j = 0; j < n; ++j)
    if (!rotations[j].coeffs().allFinite() || std::abs(rotations[j].norm() - 1.0) > 1e-6)
      fail(PLEAT_ERROR_INVALID_ARGUMENT, where + ": joint " + std::to_string(j) + " '" + s.names[j] +
                                             "' has a non-finite or non-unit rotation");
}

}  // namespace

Eigen::VectorXd Body::beta() const {
  Eigen::VectorXd b(static_cast<Eigen::Index>(shape.size()));
  for (size_t i = 0; i < shape.size(); ++i) b[static_cast<Eigen::Index>(i)] = shape[i].value;
  return b;
}

std::vector<std::string> Body::beta_names() const {
  std::vector<std::string> names;
  for (const auto& p : shape) names.push_back(p.name);
  return names;
}

void validate_body(const Body& b, const std::string& source) {
  validate_skeleton(b.skeleton, source);
  const int32_t v = b.rest.vertex_count();
  if (v == 0) fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": the body mesh has no vertices");
  for (int32_t i = 0; i < v; ++i)
    if (!b.rest.vertices.row(i).allFinite())
      fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": body vertex " + std::to_string(i) + " is not finite");
  for (int32_t f = 0; f < b.rest.triangle_count(); ++f)
    for (int c = 0; c < 3; ++c)
      if (b.rest.triangles(f, c) < 0 || b.rest.triangles(f, c) >= v)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": triangle " + std::to_string(f) + " refers to vertex " +
                                               std::to_string(b.rest.triangles(f, c)) + " of " +
                                               std::to_string(v));
  if (b.weights.joint_count != b.skeleton.joint_count())
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         source + ": skin weights are over " + std::to_string(b.weights.joint_count) +
             " joints, the skeleton has " + std::to_string(b.skeleton.joint_count()));
  validate_skin_weights(b.weights, v, source);
  if (b.pose_blend_shapes.size() != 0 &&
      (b.pose_blend_shapes.rows() != 3 * static_cast<Eigen::Index>(v) ||
       b.pose_blend_shapes.cols() != 9 * static_cast<Eigen::Index>(b.skeleton.joint_count() - 1)))
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         source + ": pose blend shapes are " + std::to_string(b.pose_blend_shapes.rows()) + " x " +
             std::to_string(b.pose_blend_shapes.cols()) + ", expected " + std::to_string(3 * v) + " x " +
             std::to_string(9 * (b.skeleton.joint_count() - 1)));
  for (const auto& p : b.shape)
    if (!std::isfinite(p.value))
      fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": shape parameter '" + p.name + "' is not finite");
}

Points3d rest_joint_positions(const Skeleton& skeleton) {
  const Transforms g = rest_transforms(skeleton);
  Points3d p(skeleton.joint_count(), 3);
  for (int32_t j = 0; j < skeleton.joint_count(); ++j) p.row(j) = g[j].translation().transpose();
  return p;
}

void pose_body(const Body& body, const Eigen::Quaterniond* rotations, const Eigen::Vector3d& root_translation,
               Points3d* posed, BodyWorkspace* workspace) {
  BodyWorkspace local;
  SkinningWorkspace& ws = workspace ? workspace->skinning : local.skinning;
  Points3d& corrected = workspace ? workspace->corrected : local.corrected;
  const int32_t n = body.skeleton.joint_count();
  check_rotations(rotations, n, body.skeleton, body.source);
  if (!root_translation.allFinite())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, body.source + ": the root translation is not finite");
  forward_kinematics(body.skeleton, rotations, root_translation, &ws.pose_global);
  ws.rest_global = rest_transforms(body.skeleton);
  skinning_matrices(ws.pose_global, ws.rest_global, &ws.matrices);
  if (body.pose_blend_shapes.size() == 0) {
    linear_blend_skinning(body.rest.vertices, body.weights, ws.matrices, posed);
    return;
  }
  Eigen::VectorXd feature(9 * (n - 1));
  for (int32_t j = 1; j < n; ++j) {
    const Eigen::Matrix3d r = rotations[j].toRotationMatrix() - Eigen::Matrix3d::Identity();
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) feature[9 * (j - 1) + 3 * a + c] = r(a, c);
  }
  const Eigen::VectorXd offsets = body.pose_blend_shapes * feature;
  corrected = body.rest.vertices + Eigen::Map<const Points3d>(offsets.data(), body.vertex_count(), 3);
  linear_blend_skinning(corrected, body.weights, ws.matrices, posed);
}

Points3d pose_body(const Body& body, const Quaternions& rotations, const Eigen::Vector3d& root_translation) {
  if (static_cast<int64_t>(rotations.size()) != body.joint_count())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, body.source + ": " + std::to_string(rotations.size()) +
                                           " pose rotations for " + std::to_string(body.joint_count()) +
                                           " joints");
  Points3d posed;
  pose_body(body, rotations.data(), root_translation, &posed);
  return posed;
}

Points3d pose_body_frames(const Body& body, const Motion& motion, int64_t first, int64_t count) {
  const int32_t n = body.joint_count();
  const Skeleton& ms = motion.skeleton;
  if (ms.joint_count() != n)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, body.source + ": the motion has " + std::to_string(ms.joint_count()) +
                                           " joints, the body " + std::to_string(n));
  for (int32_t j = 0; j < n; ++j)
    if (ms.names[j] != body.skeleton.names[j])
      fail(PLEAT_ERROR_INVALID_ARGUMENT, body.source + ": motion joint " + std::to_string(j) + " is '" +
                                             ms.names[j] + "', the body's is '" + body.skeleton.names[j] +
                                             "'");
  if (first < 0 || count < 0 || first + count > motion.frame_count)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, body.source + ": frames [" + std::to_string(first) + ", " +
                                           std::to_string(first + count) + ") outside the motion's " +
                                           std::to_string(motion.frame_count));
  if (static_cast<int64_t>(motion.rotations.size()) != motion.frame_count * n ||
      motion.root_translation.rows() != motion.frame_count)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, body.source + ": the motion's arrays disagree with its frame count");
  const Eigen::Index v = body.vertex_count();
  Points3d out(count * v, 3);
  BodyWorkspace ws;
  Points3d frame;
  for (int64_t f = 0; f < count; ++f) {
    try {
      pose_body(body, motion.frame(first + f), motion.root_translation.row(first + f).transpose(), &frame,
                &ws);
    } catch (const Error& e) {
      fail(e.status(), std::string(e.what()) + " (frame " + std::to_string(first + f) + ")");
    }
    out.middleRows(f * v, v) = frame;
  }
  return out;
}

SkinWeights nearest_vertex_weights(const Body& body, const Points3d& points) {
  SkinWeights weights;
  weights.joint_count = body.joint_count();
  for (int32_t b : nearest_points(body.rest.vertices, points)) {
    for (int32_t k = body.weights.offsets[b]; k < body.weights.offsets[b + 1]; ++k) {
      weights.joints.push_back(body.weights.joints[k]);
      weights.weights.push_back(body.weights.weights[k]);
    }
    weights.offsets.push_back(static_cast<int32_t>(weights.joints.size()));
  }
  return weights;
}

}  // namespace pleat
