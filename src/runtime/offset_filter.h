#pragma once
// The offset filter (docs/decisions/0008-offset-filter.md): each displacement
// field a learned stage adds to the posed garment (the skinned blend shapes,
// the refinement) becomes
//   x = (I + L)^{-1} d,  L = Σ_edges w_ij (e_i − e_j)(e_i − e_j)ᵀ,  w_ij = (h / l_ij)²,
// with l_ij the rest length of edge ij and h the model's
// offset_filter_length. It is implicit diffusion over a distance of about h:
// on edges much longer than h it changes little, while a cluster of edges
// much shorter than h is pulled to one displacement and moves rigidly. It
// keeps a constant field and commutes with rotations, so the refinement's
// heading frame and the world frame give the same result.
#include <Eigen/SparseCholesky>

#include "garment/garment.h"

namespace pleat::runtime {

class OffsetFilter {
 public:
  // Factorises I + L of the garment's rest edges (h > 0, in metres).
  OffsetFilter(const Garment& garment, double length);

  // In place on `frames` consecutive N x 3 row-major fields. Allocates
  // nothing (the evaluate path's promise).
  void apply(float* offsets, int64_t frames) const;
  int32_t vertex_count() const { return static_cast<int32_t>(ldlt_.rows()); }

 private:
  // Eigen's simplicial LDLᵀ (AMD ordering) rather than CHOLMOD's: its
  // triangular solves run in place on a vector of ours, where
  // cholmod_solve2 allocates on every call.
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  Eigen::VectorXd inverse_pivots_;    // D⁻¹ (vectorD() returns a copy: not per frame)
  mutable Eigen::VectorXd permuted_;  // one column, in the factor's order
};

// Edges shorter than h times this weigh as if they had that length: two
// welded-apart vertices at one position stay coupled without making I + L
// ill-conditioned (w_ij <= 10^6).
constexpr double kOffsetFilterShortestEdge = 1e-3;

}  // namespace pleat::runtime
