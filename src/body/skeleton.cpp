#include "body/skeleton.h"

#include <cmath>
#include <unordered_set>

#include "core/error.h"

namespace pleat {

int32_t Skeleton::find(const std::string& name) const {
  for (size_t j = 0; j < names.size(); ++j)
    if (names[j] == name) return static_cast<int32_t>(j);
  return -1;
}

void validate_skeleton(const Skeleton& s, const std::string& source) {
  const auto n = static_cast<size_t>(s.joint_count());
  if (n == 0) fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": skeleton has no joints");
  if (s.parents.size() != n || static_cast<size_t>(s.rest_translation.rows()) != n ||
      s.rest_rotation.size() != n)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": skeleton arrays disagree in size (" + std::to_string(n) +
                                           " names, " + std::to_string(s.parents.size()) + " parents)");
  std::unordered_set<std::string> seen;
  for (size_t j = 0; j < n; ++j) {
    const std::string joint = source + ": joint " + std::to_string(j) + " '" + s.names[j] + "'";
    if (!seen.insert(s.names[j]).second) fail(PLEAT_ERROR_INVALID_ARGUMENT, joint + " is named twice");
    if (j == 0 ? s.parents[j] != -1 : (s.parents[j] < 0 || s.parents[j] >= static_cast<int32_t>(j)))
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           joint + " has parent " + std::to_string(s.parents[j]) +
               (j == 0 ? "; the first joint must be the root (-1)"
                       : "; parents must come first (a cycle or a second root)"));
    if (!s.rest_translation.row(static_cast<Eigen::Index>(j)).allFinite() ||
        !s.rest_rotation[j].coeffs().allFinite() || std::abs(s.rest_rotation[j].norm() - 1.0) > 1e-6)
      fail(PLEAT_ERROR_INVALID_ARGUMENT, joint + " has a non-finite offset or a non-unit rest rotation");
  }
}

void forward_kinematics(const Skeleton& s, const Eigen::Quaterniond* pose, const Eigen::Vector3d& root,
                        Transforms* global) {
  const int32_t n = s.joint_count();
  global->resize(static_cast<size_t>(n));
  for (int32_t j = 0; j < n; ++j) {
    Eigen::Affine3d local = Eigen::Affine3d::Identity();
    local.translation() = j == 0 ? root : Eigen::Vector3d(s.rest_translation.row(j).transpose());
    local.linear() = (s.rest_rotation[j] * pose[j]).toRotationMatrix();
    (*global)[j] = j == 0 ? local : (*global)[s.parents[j]] * local;
  }
}

Transforms rest_transforms(const Skeleton& s) {
  Quaternions identity(static_cast<size_t>(s.joint_count()), Eigen::Quaterniond::Identity());
  Transforms global;
  forward_kinematics(s, identity.data(), s.rest_translation.row(0).transpose(), &global);
  return global;
}

}  // namespace pleat
