#pragma once
// Skeletons, poses and motions: the shared vocabulary of bodies, motion files
// and (later) the network's motion encoder.
//
// Conventions: metres, right-handed, Y up. Joints are stored parents-first
// (parents[j] < j, root has parent -1). A joint's local transform in a pose is
//   translate(rest_translation[j]) * rest_rotation[j] * pose_rotation[j]
// so a pose rotation of identity everywhere is the rest pose. BVH, SMPL and
// MakeHuman skeletons have identity rest rotations; FBX/glTF rigs may not.
// The root's local translation is replaced by the motion's root translation.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace pleat {

using Quaternions = std::vector<Eigen::Quaterniond, Eigen::aligned_allocator<Eigen::Quaterniond>>;
using Transforms = std::vector<Eigen::Affine3d, Eigen::aligned_allocator<Eigen::Affine3d>>;

struct Skeleton {
  std::vector<std::string> names;
  std::vector<int32_t> parents;  // -1 for the root; parents[j] < j
  Points3d rest_translation;     // local offset from the parent (root: global position)
  Quaternions rest_rotation;     // local rest orientation (identity for most formats)
  int32_t joint_count() const { return static_cast<int32_t>(names.size()); }
  int32_t find(const std::string& name) const;  // index or -1
};

// Frame-major joint rotations relative to the rest pose, plus the root's
// global position per frame.
struct Motion {
  Skeleton skeleton;
  double frame_rate = 30.0;
  int64_t frame_count = 0;
  Quaternions rotations;      // frame_count * joint_count, frame-major
  Points3d root_translation;  // frame_count x 3
  const Eigen::Quaterniond* frame(int64_t f) const { return rotations.data() + f * skeleton.joint_count(); }
};

// Throws PLEAT_ERROR_INVALID_ARGUMENT naming the joint: empty skeleton,
// sizes that disagree, a parent that is not earlier (cycle or bad order),
// duplicate names, non-finite or non-unit rest data.
void validate_skeleton(const Skeleton& skeleton, const std::string& source);

// Global transforms of every joint for one pose (rotations relative to rest,
// joint_count of them) and the root's global position.
void forward_kinematics(const Skeleton& skeleton, const Eigen::Quaterniond* pose_rotations,
                        const Eigen::Vector3d& root_translation, Transforms* global);

// Global rest transforms (identity pose, root at its rest translation).
Transforms rest_transforms(const Skeleton& skeleton);

}  // namespace pleat
