#pragma once
// The band basis of a garment graph (DESIGN §5): the lowest eigenvectors of
// L_norm, with the low/mid and mid/high cuts moved to spectral gaps.
#include <Eigen/Core>
#include <cstdint>

#include "core/mesh.h"
#include "spectral/band_options.h"

namespace pleat {

// A cut is moved until lambda[k] - lambda[k - 1] >= kMinGap. The band
// subspace error is about residual / gap (Davis-Kahan): with solver residuals
// <= 1e-11 this keeps projections stable to ~1e-6 even at the smallest gap,
// while exact repeats (mirrored panels, gap ~1e-15) are never split. Gaps
// this small are otherwise rare: neighbouring eigenvalues of a 20k-vertex
// garment are ~1e-4 apart near the mid cut.
constexpr double kMinGap = 1e-5;

template <typename Scalar>
struct BandBasis {
  int32_t vertex_count = 0;
  int32_t low_count = 0;                  // eigenvectors in the low band (after the gap move)
  int32_t mid_count = 0;                  // eigenvectors in low + mid (after the gap move)
  int32_t low_requested = 0;              // ceil(N * low_fraction)
  int32_t mid_requested = 0;              // ceil(N * mid_fraction)
  SolverKind solver = SolverKind::dense;  // the one actually used (never automatic)
  ProjectionForm projection = ProjectionForm::random_walk;
  // lambda[count] - lambda[count - 1]; +infinity when count == N (nothing above).
  double low_gap = 0.0;
  double mid_gap = 0.0;
  // The lowest mid_count + 1 eigenvalues (mid_count when mid_count == N): the
  // extra one shows mid_gap.
  Eigen::VectorXd eigenvalues;
  // N x mid_count orthonormal eigenvectors of L_norm, ascending eigenvalue.
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> vectors;
  // sqrt(degree), 1 for isolated vertices (the random-walk scaling).
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> sqrt_degree;

  template <typename T>
  BandBasis<T> cast() const {
    BandBasis<T> b;
    b.vertex_count = vertex_count;
    b.low_count = low_count;
    b.mid_count = mid_count;
    b.low_requested = low_requested;
    b.mid_requested = mid_requested;
    b.solver = solver;
    b.projection = projection;
    b.low_gap = low_gap;
    b.mid_gap = mid_gap;
    b.eigenvalues = eigenvalues;
    b.vectors = vectors.template cast<T>();
    b.sqrt_degree = sqrt_degree.template cast<T>();
    return b;
  }
};

// Throws PLEAT_ERROR_INVALID_ARGUMENT naming the field when options are bad.
void validate_band_options(const BandOptions& options);

// Solves for the band basis of `graph`. Throws PLEAT_ERROR_INVALID_ARGUMENT
// (bad options, empty graph) or PLEAT_ERROR_NUMERICAL (solver failure).
BandBasis<double> compute_band_basis(const Csr& graph, const BandOptions& options);

// The cut nearest `requested` (ties go up) with lambda[k] - lambda[k-1] >=
// min_gap and k >= min_cut, using the known `values` (the lowest of
// `vertex_count`; k == vertex_count always qualifies). Returns -1 when an
// unknown eigenvalue could still give a nearer cut (solve for more).
int nearest_gap_cut(const Eigen::VectorXd& values, int vertex_count, int requested, int min_cut,
                    double min_gap);

}  // namespace pleat
