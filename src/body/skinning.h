#pragma once
// Skin weights and linear blend skinning (LBS).
//
// Weights are sparse per vertex (compressed rows): the influences of vertex v
// are joints[offsets[v] .. offsets[v+1]) with weights[...] at the same slots,
// joint indices strictly ascending within a vertex. A valid set has indices in
// range, finite non-negative weights and per-vertex sums of 1 within 1e-3.
//
// Skinning matrix of joint j: S_j = G_pose[j] * G_rest[j]^-1 (global
// transforms of the pose and of the rest pose), and a vertex moves to
// sum_j w_vj * S_j * v. The sum runs over joints in ascending order, so the
// sparse and dense paths give bit-identical results for the same weights.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "body/skeleton.h"
#include "core/mesh.h"

namespace pleat {

struct SkinWeights {
  int32_t joint_count = 0;
  std::vector<int32_t> offsets{0};  // vertex_count + 1
  std::vector<int32_t> joints;      // ascending within a vertex
  std::vector<double> weights;
  int32_t vertex_count() const { return static_cast<int32_t>(offsets.size()) - 1; }
  int32_t influences(int32_t v) const { return offsets[v + 1] - offsets[v]; }
  int32_t max_influences() const;
};

// Tolerance on each vertex's weight sum.
constexpr double kSkinWeightSumTolerance = 1e-3;

// Throws PLEAT_ERROR_INVALID_ARGUMENT naming `source` and the vertex: array
// sizes, vertex count != expected_vertices (skipped when < 0), joint index out
// of range or repeated/unsorted, non-finite or negative weight, a sum off 1.
void validate_skin_weights(const SkinWeights& weights, int32_t expected_vertices, const std::string& source);

// For loaders: merges repeated joints of a vertex, sorts by joint, drops zero
// weights and rescales each vertex to sum 1. Throws PLEAT_ERROR_INVALID_ARGUMENT
// naming the vertex for an index out of range, a non-finite or negative weight,
// or a vertex without any positive weight.
void normalize_skin_weights(SkinWeights* weights, const std::string& source);

// Builds sparse weights from a dense vertex_count x joint_count matrix, keeping
// entries > threshold (no renormalisation: call normalize_skin_weights).
SkinWeights skin_weights_from_dense(const Eigen::Ref<const Eigen::MatrixXd>& dense, double threshold = 0.0);

// Dense vertex_count x joint_count matrix of the weights.
Eigen::MatrixXd dense_skin_weights(const SkinWeights& weights);

// Keeps the k largest weights of each vertex (ties: lower joint index first)
// and renormalises those vertices that lost an influence; vertices with k or
// fewer influences are copied unchanged. k >= 1.
SkinWeights truncate_skin_weights(const SkinWeights& weights, int32_t k);

// 3x4 affine skinning matrices [R | t], one per joint.
using SkinMatrix = Eigen::Matrix<double, 3, 4>;
using SkinMatrices = std::vector<SkinMatrix, Eigen::aligned_allocator<SkinMatrix>>;

// out[j] = pose_global[j] * rest_global[j]^-1 (sizes must agree; out resized).
void skinning_matrices(const Transforms& pose_global, const Transforms& rest_global, SkinMatrices* out);

// LBS of `rest` (vertex_count x 3) into `posed` (same size, may not alias
// `rest`). Scalar is float or double; blending is done in double.
template <typename Scalar>
void linear_blend_skinning(const Points<Scalar>& rest, const SkinWeights& weights,
                           const SkinMatrices& matrices, Points<Scalar>* posed);

// Same with dense weights (vertex_count x joint_count); zero weights skipped.
template <typename Scalar>
void linear_blend_skinning_dense(const Points<Scalar>& rest, const Eigen::Ref<const Eigen::MatrixXd>& weights,
                                 const SkinMatrices& matrices, Points<Scalar>* posed);

// Scratch space reused across frames so the per-frame path does not allocate
// once it has grown to the skeleton's size.
struct SkinningWorkspace {
  Transforms rest_global;
  Transforms pose_global;
  SkinMatrices matrices;
};

// Skins `count` frames of `motion` starting at `first` (the motion's skeleton
// must be the one the weights were made for). Writes count * vertex_count * 3
// values, frame-major, xyz per vertex, into `out` (out_size values available).
// Throws PLEAT_ERROR_INVALID_ARGUMENT for a frame range outside the motion,
// a weights/skeleton/mesh mismatch or a too small buffer
// (PLEAT_ERROR_BUFFER_TOO_SMALL).
template <typename Scalar>
void skin_frames(const Points<Scalar>& rest, const SkinWeights& weights, const Motion& motion, int64_t first,
                 int64_t count, SkinningWorkspace* workspace, Scalar* out, size_t out_size);

}  // namespace pleat
