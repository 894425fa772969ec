#pragma once
// Spectrum slicing for L_norm: Sylvester-inertia eigenvalue counts and
// shift-invert Lanczos (Spectra) for every eigenpair inside an interval.
// Shared by the slicing and the hybrid solvers.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "spectral/eigen_pairs.h"
#include "spectral/shifted_ldlt.h"

namespace pleat {

// A shift and the number of eigenvalues strictly below it.
struct Shift {
  double sigma;
  int below;
};

// Every eigenvalue of L_norm lies in [0, 2]; shifts just outside bracket them.
constexpr double kShiftBelowSpectrum = -1e-3;
constexpr double kShiftAboveSpectrum = 2.0 + 1e-3;

class Slicer {
 public:
  explicit Slicer(const Eigen::SparseMatrix<double>& laplacian);

  // Counts the eigenvalues below sigma from the LDL^T inertia. sigma is moved
  // by a few 1e-7 when a pivot is below kPivotFloor (an eigenvalue next to
  // sigma): the count of the moved shift is exact, the one at sigma might not be.
  Shift count_below(double sigma);
  // Shift above every eigenvalue (not factorised: none is needed).
  Shift top() const { return {kShiftAboveSpectrum, static_cast<int>(laplacian_.rows())}; }

  // A shift in (lo, hi) with target <= below <= target + slack, found by
  // safeguarded interpolation on the counting function. `guess` (if inside
  // the bracket) is tried first. Returns the closest count above target when
  // a degenerate cluster makes the range unreachable.
  Shift place_boundary(Shift lo, Shift hi, int target, int slack, double guess);

  // All eigenpairs with lo.sigma <= lambda < hi.sigma, ascending; their number
  // is checked against the inertia difference. `label` names the slice in errors.
  EigenPairs solve_interval(const Shift& lo, const Shift& hi, const std::string& label);

 private:
  const Eigen::SparseMatrix<double>& laplacian_;
  ShiftedLdlt ldlt_;
};

// Concatenates slices (ascending, disjoint), then repairs orthogonality across
// each boundary: vectors from two shifts are orthogonal only to about
// residual / (eigenvalue distance), so the pairs within kBoundaryWindow of a
// boundary get a joint Rayleigh-Ritz.
EigenPairs merge_slices(const Eigen::SparseMatrix<double>& laplacian, const std::vector<EigenPairs>& slices,
                        const std::vector<double>& boundaries);

// Keeps the first `count` pairs.
void truncate_pairs(EigenPairs* pairs, int count);

}  // namespace pleat
