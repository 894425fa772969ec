#pragma once
// A body: skeleton + rest mesh + skin weights + the shape vector β that made
// them. Bodies come from the MakeHuman open model (body/makehuman.h), from an
// SMPL-layout .npz (body/smpl_npz.h) or from any rigged FBX/glTF character
// (body/rig_import.h); all of them end up as this one type.
//
// Conventions (skeleton.h): metres, right-handed, Y up; joints parents-first.
// The skeleton's rest_translation already holds the joints of the current
// shape J(β) (the root's row is its global rest position), so a Body is a
// snapshot of one shape: changing β means asking the model for a new Body.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "body/skeleton.h"
#include "body/skinning.h"
#include "core/mesh.h"

namespace pleat {

// One entry of β.
struct ShapeParameter {
  std::string name;
  double value = 0.0;
  double default_value = 0.0;
  double min = 0.0;  // the documented range; values outside it are refused by
  double max = 1.0;  // the model that defines the parameter
  std::string description;
};

struct Body {
  std::string source;                 // where it came from, for messages ("makehuman:cmu_mb", a path)
  Skeleton skeleton;                  // rest joints J(β)
  TriMesh rest;                       // rest surface, metres, Y up
  SkinWeights weights;                // rest.vertex_count() rows over skeleton.joint_count() joints
  std::vector<ShapeParameter> shape;  // β definition and current values (may be empty)
  // Optional SMPL-style pose corrective blend shapes: (3 V) x 9 (J - 1); row
  // 3 v + k is coordinate k of vertex v; column 9 (j - 1) + 3 r + c multiplies
  // (R_j - I)(r, c) of joint j's pose rotation (relative to rest). Empty when
  // the body has none.
  Eigen::MatrixXd pose_blend_shapes;

  int32_t vertex_count() const { return rest.vertex_count(); }
  int32_t joint_count() const { return skeleton.joint_count(); }
  Eigen::VectorXd beta() const;  // current β values
  std::vector<std::string> beta_names() const;
};

// Throws PLEAT_ERROR_INVALID_ARGUMENT naming `source` and the offending joint,
// vertex or field: skeleton (validate_skeleton), empty or non-finite mesh,
// triangle indices out of range, weights (validate_skin_weights) that do not
// match the mesh or skeleton, pose blend shapes of the wrong size.
void validate_body(const Body& body, const std::string& source);

// Skin weights for arbitrary points (a garment) copied from the nearest rest
// body vertex of each: the plain LBS that the network is compared with, and
// what datagen pins follow.
SkinWeights nearest_vertex_weights(const Body& body, const Points3d& points);

// Global rest positions of the joints (joint_count x 3).
Points3d rest_joint_positions(const Skeleton& skeleton);

// Scratch space reused across frames.
struct BodyWorkspace {
  SkinningWorkspace skinning;
  Points3d corrected;  // rest + pose blend shapes
};

// Posed vertices for one pose: `rotations` holds joint_count rotations
// relative to rest (skeleton.h), `root_translation` the root joint's global
// position (the rest pose is root_translation = skeleton.rest_translation
// row 0). Pose blend shapes, when present, are added before skinning. Uses
// the LBS of body/skinning.h. `workspace` may be null.
void pose_body(const Body& body, const Eigen::Quaterniond* rotations, const Eigen::Vector3d& root_translation,
               Points3d* posed, BodyWorkspace* workspace = nullptr);
Points3d pose_body(const Body& body, const Quaternions& rotations, const Eigen::Vector3d& root_translation);

// Posed vertices of frames [first, first + count) of a motion, frame-major:
// ((count * vertex_count) x 3). The motion's skeleton must have the body's
// joint names in the body's order (checked; message names the first joint
// that differs); its rest offsets are not used: the body's own skeleton
// carries the shape. Throws PLEAT_ERROR_INVALID_ARGUMENT for a frame range
// outside the motion, a non-finite or non-unit rotation (frame and joint named).
Points3d pose_body_frames(const Body& body, const Motion& motion, int64_t first, int64_t count);

}  // namespace pleat
