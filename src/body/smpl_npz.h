#pragma once
// SMPL-layout bodies from .npz files, for users who hold an SMPL (or SMPL-H,
// SMPL-X body-only) licence. pleat ships no SMPL data; see docs/bodies.md.
//
// Arrays read (others are ignored; V vertices, J joints, B shape directions):
//   v_template    V x 3
//   shapedirs     V x 3 x B
//   posedirs      V x 3 x 9 (J - 1)
//   J_regressor   J x V (dense)
//   weights       V x J (rows sum to 1)
//   kintree_table 2 x J: row 0 parents (root -1 or 4294967295), row 1 = 0..J-1
//   f             F x 3 triangle indices
// Any of the dtypes io/npz.h reads, C or Fortran order.
//
// The SMPL formulas: v_shaped = v_template + shapedirs . β;
// J = J_regressor . v_shaped; v_posed = v_shaped + posedirs . P(θ) with
// P(θ) = concat over joints 1..J-1 of (R(θ_j) - I) flattened row-major;
// v = LBS(v_posed) with the weights and the joints J. Units are the file's
// (SMPL: metres, Y up).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "body/body.h"

namespace pleat {

struct SmplModel {
  std::string source;                    // the file
  Points3d v_template;                   // V x 3
  Eigen::MatrixXd shapedirs;             // 3V x B, row 3 v + k
  Eigen::MatrixXd posedirs;              // 3V x 9 (J - 1)
  Eigen::MatrixXd j_regressor;           // J x V
  SkinWeights weights;                   // V rows over J joints (as in the file, not renormalised)
  std::vector<int32_t> parents;          // J, root -1, parents first
  std::vector<std::string> joint_names;  // SMPL's 24 names when J == 24, else "joint_<i>"
  Triangles faces;
  int32_t vertex_count() const { return static_cast<int32_t>(v_template.rows()); }
  int32_t joint_count() const { return static_cast<int32_t>(parents.size()); }
  int32_t shape_count() const { return static_cast<int32_t>(shapedirs.cols()); }
};

// Loads and validates. Throws PLEAT_ERROR_IO (unreadable file),
// PLEAT_ERROR_FORMAT (not an npz, corrupt, a missing array — named — or a
// wrong shape — array and shapes named) or PLEAT_ERROR_INVALID_ARGUMENT for
// bad values: non-finite entries (array and index named), weights negative
// or not summing to 1 (vertex named), a kintree with a cycle, a second root
// or a parent after its child (joint named), faces out of range.
SmplModel load_smpl_npz(const std::string& path);

// v_shaped (V x 3). β may be shorter than B (missing entries are 0), not longer.
Points3d smpl_shaped_vertices(const SmplModel& model, const Eigen::VectorXd& beta);

// J = J_regressor . shaped (J x 3).
Points3d smpl_joints(const SmplModel& model, const Points3d& shaped);

// The body of shape β: rest mesh v_shaped, skeleton with joints J(β) and
// identity rest rotations, the weights, posedirs as pose blend shapes, and
// β as B shape parameters "beta_<i>" (range -5..5, default 0). Posing it
// with pose_body(body, R, J_0 + trans) gives SMPL's vertices for pose R and
// translation trans.
Body smpl_body(const SmplModel& model, const Eigen::VectorXd& beta);

// SMPL poses are axis-angle vectors: one row per joint (J x 3) to rotations.
Quaternions smpl_pose_rotations(const Eigen::Ref<const Eigen::MatrixXd>& axis_angle);

// Posed vertices for β, axis-angle pose (J x 3) and global translation.
Points3d smpl_posed_vertices(const SmplModel& model, const Eigen::VectorXd& beta,
                             const Eigen::Ref<const Eigen::MatrixXd>& axis_angle,
                             const Eigen::Vector3d& translation);

}  // namespace pleat
