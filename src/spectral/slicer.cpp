#include "spectral/slicer.h"

#include <Spectra/SymEigsShiftSolver.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "core/error.h"

namespace pleat {
namespace {

// A pivot this small means sigma sits within about this distance of an
// eigenvalue: the unpivoted LDL^T is then unreliable, so sigma moves.
constexpr double kPivotFloor = 1e-9;
constexpr double kShiftJitter = 1e-7;
constexpr int kMaxJitters = 12;
// Lanczos stopping tolerance, relative to the shift-inverted Ritz value; gives
// residuals ||L v - lambda v|| of about 2e-13 (checked against kResidualTolerance).
constexpr double kLanczosTolerance = 1e-13;
constexpr int kMaxLanczosRestarts = 2000;
// Extra eigenpairs requested around a slice centre: the nearest ones need not
// all lie inside the slice when the density is lopsided.
constexpr int kMinExtraPairs = 8;
constexpr int kMaxSliceRounds = 8;
constexpr double kBoundaryWindow = 1e-4;

// (L - sigma I)^{-1} restricted to the complement of already found vectors:
// y = P (L - sigma I)^{-1} P x with P = I - Q Q^T. Deflation is what lets a
// single-vector Lanczos find every copy of a repeated eigenvalue.
class DeflatedShiftInvert {
 public:
  using Scalar = double;
  DeflatedShiftInvert(const ShiftedLdlt& ldlt, const Eigen::MatrixXd& deflate)
      : ldlt_(ldlt), deflate_(deflate), buffer_(ldlt.rows()) {}
  Eigen::Index rows() const { return ldlt_.rows(); }
  Eigen::Index cols() const { return ldlt_.rows(); }
  // Spectra passes the shift it was built with: always ldlt_.sigma().
  void set_shift(double /*sigma*/) {}
  void perform_op(const double* x_in, double* y_out) const {
    Eigen::Map<const Eigen::VectorXd> x(x_in, rows());
    Eigen::Map<Eigen::VectorXd> y(y_out, rows());
    buffer_ = x;
    project(&buffer_);
    ldlt_.solve(buffer_.data(), y_out);
    if (deflate_.cols() > 0) y -= deflate_ * (deflate_.transpose() * y);
  }
  void project(Eigen::VectorXd* v) const {
    if (deflate_.cols() > 0) *v -= deflate_ * (deflate_.transpose() * *v);
  }

 private:
  const ShiftedLdlt& ldlt_;
  const Eigen::MatrixXd& deflate_;
  mutable Eigen::VectorXd buffer_;
};

std::string interval_text(const Shift& lo, const Shift& hi) {
  return "[" + std::to_string(lo.sigma) + ", " + std::to_string(hi.sigma) + ")";
}

}  // namespace

Slicer::Slicer(const Eigen::SparseMatrix<double>& laplacian) : laplacian_(laplacian), ldlt_(laplacian) {}

Shift Slicer::count_below(double sigma) {
  double shifted = sigma;
  for (int attempt = 0; attempt < kMaxJitters; ++attempt) {
    ldlt_.factorize(shifted);
    if (ldlt_.min_abs_pivot() > kPivotFloor) return {shifted, ldlt_.negative_pivots()};
    // Alternate sides with growing steps: +1, -2, +3, ... times the jitter.
    shifted = sigma + kShiftJitter * (attempt + 1) * (attempt % 2 == 0 ? 1.0 : -1.0);
  }
  fail(PLEAT_ERROR_NUMERICAL,
       "LDL^T of L - sigma I has a zero pivot at every shift near sigma = " + std::to_string(sigma));
}

Shift Slicer::place_boundary(Shift lo, Shift hi, int target, int slack, double guess) {
  if (hi.below >= target && hi.below <= target + slack) return hi;
  const double aim = target + 0.5 * slack;
  const Shift start = lo;
  bool hi_is_local = false;  // hi came from this search, not a far-away caller bracket
  double sigma = guess;
  for (int step = 0; step < 200; ++step) {
    const double width = hi.sigma - lo.sigma;
    if (width < 1e-10) return hi;  // a cluster larger than the slack straddles the target
    // The caller's guess only has to lie inside the bracket: a margin
    // relative to a bracket reaching the top of the spectrum would reject
    // every guess near the bottom (it did: ~3 factorisations per boundary).
    if (step > 0 || !(sigma > lo.sigma && sigma < hi.sigma)) {
      // Interpolate the counting function, kept 5% inside the bracket so
      // the bracket shrinks every step even where the density is skewed.
      double t = std::clamp((aim - lo.below) / std::max(1, hi.below - lo.below), 0.05, 0.95);
      if (!hi_is_local && lo.below > start.below) {
        // The upper end is still the caller's: extrapolate the density
        // between start and lo instead of a chord to the far end. Every
        // step raises lo or makes hi local, so the search still terminates.
        const double local = (lo.sigma - start.sigma) / (lo.below - start.below);
        t = std::clamp((aim - lo.below) * local / width, 1e-6, 0.95);
      }
      sigma = lo.sigma + t * width;
    }
    const Shift s = count_below(sigma);
    if (s.below >= target && s.below <= target + slack) return s;
    if (s.below < target) {
      lo = s;
    } else {
      hi = s;
      hi_is_local = true;
    }
  }
  fail(PLEAT_ERROR_NUMERICAL,
       "could not place a slice boundary with " + std::to_string(target) + " eigenvalues below it");
}

EigenPairs Slicer::solve_interval(const Shift& lo, const Shift& hi, const std::string& label) {
  const int n = static_cast<int>(laplacian_.rows());
  const int expected = hi.below - lo.below;
  EigenPairs inside;
  inside.values.resize(0);
  inside.vectors.resize(n, 0);
  if (expected == 0) return inside;
  const Shift centre = count_below(0.5 * (lo.sigma + hi.sigma));
  Eigen::MatrixXd deflate(n, 0);
  std::vector<double> values;
  std::vector<Eigen::VectorXd> vectors;
  std::mt19937 rng(12345);
  std::normal_distribution<double> normal;
  DeflatedShiftInvert op(ldlt_, deflate);
  for (int round = 0; round < kMaxSliceRounds && static_cast<int>(values.size()) < expected; ++round) {
    const int missing = expected - static_cast<int>(values.size());
    const int available = n - static_cast<int>(deflate.cols());
    const int nev = std::min(missing + std::max(kMinExtraPairs, missing / 4), available - 1);
    if (nev < 1) break;
    // ncv = 1.5 nev (not Spectra's usual 2 nev): more restarts, but each
    // Lanczos step reorthogonalises against fewer vectors; measured ~5 %
    // faster for 40-100 pairs a slice.
    const int ncv = std::min(available, std::max(nev + nev / 2 + 1, nev + 24));
    Eigen::VectorXd start = Eigen::VectorXd::NullaryExpr(n, [&]() { return normal(rng); });
    op.project(&start);
    Spectra::SymEigsShiftSolver<DeflatedShiftInvert> eigs(op, nev, ncv, centre.sigma);
    eigs.init(start.data());
    eigs.compute(Spectra::SortRule::LargestMagn, kMaxLanczosRestarts, kLanczosTolerance,
                 Spectra::SortRule::SmallestAlge);
    const Eigen::VectorXd found_values = eigs.eigenvalues();
    const Eigen::MatrixXd found_vectors = eigs.eigenvectors();
    const Eigen::VectorXd residuals =
        (laplacian_ * found_vectors - found_vectors * found_values.asDiagonal()).colwise().norm();
    std::vector<Eigen::Index> accepted;  // inaccurate pairs are left for the next round
    for (Eigen::Index j = 0; j < found_values.size(); ++j) {
      if (!(residuals[j] <= kResidualTolerance)) continue;
      accepted.push_back(j);
      if (found_values[j] >= lo.sigma && found_values[j] < hi.sigma) {
        values.push_back(found_values[j]);
        vectors.push_back(found_vectors.col(j));
      }
    }
    if (accepted.empty()) break;
    const Eigen::Index old_cols = deflate.cols();
    deflate.conservativeResize(Eigen::NoChange, old_cols + static_cast<Eigen::Index>(accepted.size()));
    for (size_t j = 0; j < accepted.size(); ++j)
      deflate.col(old_cols + static_cast<Eigen::Index>(j)) = found_vectors.col(accepted[j]);
  }
  if (static_cast<int>(values.size()) != expected)
    fail(PLEAT_ERROR_NUMERICAL, "slicing eigensolver: " + label + " " + interval_text(lo, hi) + " (shift " +
                                    std::to_string(centre.sigma) + ") found " +
                                    std::to_string(values.size()) + " eigenpairs, inertia says " +
                                    std::to_string(expected));
  inside.values = Eigen::Map<const Eigen::VectorXd>(values.data(), expected);
  inside.vectors.resize(n, expected);
  for (int j = 0; j < expected; ++j) inside.vectors.col(j) = vectors[static_cast<size_t>(j)];
  sort_pairs(&inside);
  return inside;
}

EigenPairs merge_slices(const Eigen::SparseMatrix<double>& laplacian, const std::vector<EigenPairs>& slices,
                        const std::vector<double>& boundaries) {
  Eigen::Index total = 0;
  for (const EigenPairs& s : slices) total += s.values.size();
  EigenPairs all;
  all.values.resize(total);
  all.vectors.resize(laplacian.rows(), total);
  Eigen::Index at = 0;
  for (const EigenPairs& s : slices) {
    all.values.segment(at, s.values.size()) = s.values;
    all.vectors.middleCols(at, s.values.size()) = s.vectors;
    at += s.values.size();
  }
  // Slices arrive ascending and disjoint; sorting (a full copy) is only a
  // safeguard.
  if (!std::is_sorted(all.values.data(), all.values.data() + total)) sort_pairs(&all);
  for (double boundary : boundaries) {
    Eigen::Index first = 0;
    while (first < total && all.values[first] < boundary - kBoundaryWindow) ++first;
    Eigen::Index last = first;
    while (last < total && all.values[last] < boundary + kBoundaryWindow) ++last;
    const bool straddles = first < last && all.values[first] < boundary && all.values[last - 1] >= boundary;
    if (!straddles) continue;
    const EigenPairs repaired = rayleigh_ritz(laplacian, all.vectors.middleCols(first, last - first));
    all.values.segment(first, last - first) = repaired.values;
    all.vectors.middleCols(first, last - first) = repaired.vectors;
  }
  return all;
}

void truncate_pairs(EigenPairs* pairs, int count) {
  if (pairs->values.size() <= count) return;
  pairs->values.conservativeResize(count);
  pairs->vectors.conservativeResize(Eigen::NoChange, count);
}

}  // namespace pleat
