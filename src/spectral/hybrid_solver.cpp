#include "spectral/hybrid_solver.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <random>
#include <string>

#include "core/error.h"
#include "spectral/chebyshev_filter.h"
#include "spectral/slicer.h"

namespace pleat {
namespace {

// Window of exact eigenpairs: wide enough that the filter's transition band
// [a, b] needs a moderate degree, narrow enough for one Lanczos slice.
constexpr int kMinWindow = 32;
constexpr int kWindowDivisor = 8;
// Per-iteration damping of the unwanted part; ~4 iterations reach 1e-12.
constexpr double kFilterRatio = 1e-3;
constexpr int kMaxFilterDegree = 4000;
constexpr int kMaxFilterIterations = 40;

// CholQR2: two Cholesky-QR passes orthonormalise the columns to round-off as
// long as they are not nearly dependent (the filter keeps them well apart).
void orthonormalize(Eigen::MatrixXd* v) {
  for (int pass = 0; pass < 2; ++pass) {
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(v->cols(), v->cols());
    gram.selfadjointView<Eigen::Lower>().rankUpdate(v->transpose());
    Eigen::LLT<Eigen::MatrixXd> llt(gram);
    if (llt.info() != Eigen::Success)
      fail(PLEAT_ERROR_NUMERICAL, "hybrid eigensolver: filtered block lost rank");
    llt.matrixU().solveInPlace<Eigen::OnTheRight>(*v);
  }
}

void deflate(const Eigen::MatrixXd& window, Eigen::MatrixXd* v) {
  *v -= window * (window.transpose() * *v);
}

// The `count` lowest eigenpairs, all below pass_edge, orthogonal to `window`
// (which spans every eigenvector in [pass_edge, stop_edge)).
EigenPairs filtered_subspace(const Eigen::SparseMatrix<double>& laplacian, int count, double pass_edge,
                             double stop_edge, const Eigen::MatrixXd& window) {
  const ChebyshevFilter filter(pass_edge, stop_edge, kFilterRatio, kMaxFilterDegree);
  std::mt19937 rng(2024);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd v = Eigen::MatrixXd::NullaryExpr(laplacian.rows(), count, [&]() { return normal(rng); });
  Eigen::MatrixXd filtered;
  EigenPairs pairs;
  double residual = 0.0;
  for (int iteration = 0; iteration < kMaxFilterIterations; ++iteration) {
    filter.apply(laplacian, v, &filtered);
    deflate(window, &filtered);
    orthonormalize(&filtered);
    const Eigen::MatrixXd lv = laplacian * filtered;
    Eigen::MatrixXd h = filtered.transpose() * lv;
    h = 0.5 * (h + h.transpose()).eval();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz(h);
    pairs.values = ritz.eigenvalues();
    pairs.vectors = filtered * ritz.eigenvectors();
    residual =
        (lv * ritz.eigenvectors() - pairs.vectors * pairs.values.asDiagonal()).colwise().norm().maxCoeff();
    if (residual <= kResidualTolerance) {
      if (pairs.values.maxCoeff() >= pass_edge)
        fail(PLEAT_ERROR_NUMERICAL, "hybrid eigensolver: filtered iteration converged above the window");
      return pairs;
    }
    v.swap(pairs.vectors);
  }
  fail(PLEAT_ERROR_NUMERICAL, "hybrid eigensolver: filtered subspace iteration (degree " +
                                  std::to_string(filter.degree()) + ") stalled at residual " +
                                  std::to_string(residual));
}

}  // namespace

EigenPairs solve_hybrid(const Eigen::SparseMatrix<double>& laplacian, int count) {
  Slicer slicer(laplacian);
  const Shift bottom = slicer.count_below(kShiftBelowSpectrum);
  const int window = std::max(kMinWindow, count / kWindowDivisor);
  if (count <= 2 * window) {
    // Too few pairs for a filtered bulk: the window is the whole range.
    const Shift hi = slicer.place_boundary(bottom, slicer.top(), count, window / 4, -1.0);
    EigenPairs pairs = slicer.solve_interval(bottom, hi, "hybrid window");
    truncate_pairs(&pairs, count);
    return pairs;
  }
  const Shift a = slicer.place_boundary(bottom, slicer.top(), count - window, window / 4, -1.0);
  const Shift b = slicer.place_boundary(a, slicer.top(), count, window / 4, -1.0);
  const EigenPairs exact = slicer.solve_interval(a, b, "hybrid window");
  const EigenPairs bulk = filtered_subspace(laplacian, a.below, a.sigma, b.sigma, exact.vectors);
  EigenPairs pairs = merge_slices(laplacian, {bulk, exact}, {a.sigma});
  truncate_pairs(&pairs, count);
  return pairs;
}

}  // namespace pleat
