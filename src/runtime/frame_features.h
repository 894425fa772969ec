#pragma once
// The network's inputs computed from a body and its poses (docs/runtime.md
// defines each one). Shared by the Instance and by the trainer, so both feed
// the network exactly the same numbers.
//
// The root frame: the network never sees where the character stands or which
// way it faces. Frame t's heading H_t is the rotation about +Y that best
// matches the root's rotation relative to its rest orientation,
//   P_f = R_rest,root * pose_root,f * R_rest,root^-1,
// (atan2 of its +Z axis projected on the ground plane; its +X axis when +Z
// points straight up or down). Directions the network reads (root
// orientation, root velocity, garment velocities and normals) are expressed
// in H_t, and the refinement's offsets are rotated back by H_t.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "body/skeleton.h"
#include "body/skinning.h"
#include "garment/garment.h"
#include "nn/tensor.h"
#include "runtime/instance.h"
#include "runtime/model.h"

namespace pleat::runtime {

class FrameFeatures {
 public:
  FrameFeatures() = default;
  // body_of_model[j] = the body joint that model joint j reads (poses come in
  // the body's order).
  FrameFeatures(const Model& model, const Skeleton& body_skeleton, std::vector<int32_t> body_of_model);

  // H_t (see above) of frame t; frames before 0 are frame 0.
  Eigen::Matrix3d heading(const PoseSequence& poses, int64_t t) const;

  // Garment-encoder input per rest vertex, in the stack's feature order:
  // rest_position (relative to the root joint's rest position), rest_normal,
  // rest_joint_distances (to rest_joints, model order). out: N x width.
  void rest_garment(const Garment& garment, const Points3d& rest_joints, nn::MatrixRM& out) const;

  // Motion-encoder input of frame t's window, one row per step (oldest
  // first): frames t - window + 1 .. t, those before 0 repeating frame 0.
  // joint_rotations_6d: per model joint the first two columns of its rotation
  // (the root: H_t^-1 P_f; the others: their pose rotation relative to rest),
  // column by column; root_velocity: H_t^-1 (x_f - x_{f-1}) * fps (0 at f = 0).
  void motion_window(const PoseSequence& poses, int64_t t, nn::MatrixRM& out) const;

  // Forward kinematics of frame t: skinning matrices [R | t] (row-major 3x4,
  // 12 floats per row) and posed joint positions, both in model order. The
  // workspaces (body order) must be sized to the joint count.
  void skinning_matrices(const PoseSequence& poses, int64_t t, Quaternions& pose, Transforms& pose_global,
                         const Transforms& rest_global, SkinMatrices& matrices, nn::MatrixRM& skin,
                         nn::MatrixRM& joint_positions) const;

  // The vertex's row of F^t as its two factors: (G ⊙ b) of the vertex and
  // q^t of the frame, `width` floats each (unread without fused_code).
  struct FusedCode {
    const float* garment_body = nullptr;
    const float* motion = nullptr;
    Index width = 0;
  };

  // One vertex's refinement input in `features` order: velocity and normal
  // in H_t (heading passed as H_t), posed_joint_distances from `position`,
  // fused_code = (G ⊙ b) ⊙ q^t.
  void refinement_row(const std::vector<Feature>& features, const Eigen::Matrix3f& heading,
                      const Eigen::Vector3f& velocity, const Eigen::Vector3f& normal,
                      const Eigen::Vector3f& position, const nn::MatrixRM& joint_positions,
                      const FusedCode& code, float* out) const;

 private:
  Eigen::Quaterniond rotation(const PoseSequence& poses, int64_t f, int32_t body_joint) const;
  Eigen::Matrix3d root_relative(const PoseSequence& poses, int64_t f) const;

  std::vector<Feature> motion_features_;
  std::vector<Feature> garment_features_;
  std::vector<int32_t> body_of_model_;
  Eigen::Quaterniond root_rest_ = Eigen::Quaterniond::Identity();
  const Skeleton* skeleton_ = nullptr;
  int32_t window_ = 1;
  double frame_rate_ = 30.0;
};

// Skinning weights of one vertex from its S logits: the k largest (ties:
// lower joint first), softmax over those k alone (= the full softmax
// truncated to k and renormalised). weights / joints receive k entries in no
// set order (LBS does not need one). k is at most S.
void top_k_softmax(const float* logits, int32_t joint_count, int32_t k, float* weights, int32_t* joints);

}  // namespace pleat::runtime
