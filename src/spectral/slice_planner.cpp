#include "spectral/slice_planner.h"

#include <algorithm>

namespace pleat {

SlicePlanner::SlicePlanner(const Eigen::SparseMatrix<double>& laplacian, int count, int slice_size)
    : counter_(laplacian),
      count_(count),
      slice_size_(slice_size),
      lo_(counter_.count_below(kShiftBelowSpectrum)) {}

std::optional<SliceBounds> SlicePlanner::next() {
  if (lo_.below >= count_) return std::nullopt;
  const int remaining = count_ - lo_.below;
  // Any slice of slice/2 .. 3 slice/2 eigenvalues is accepted: the density
  // of the counting function fluctuates by about +-50 % between neighbouring
  // slices (symmetric meshes add jumps of 2-4), and a range of slice/4 was
  // missed by most first guesses, each miss costing one more factorisation.
  // A short tail joins the last slice, which stops close to count.
  const bool last = remaining <= slice_size_ * 3 / 2;
  const int target = last ? count_ : lo_.below + slice_size_ / 2;
  const int slack = last ? std::max(1, slice_size_ / 4) : slice_size_;
  // Aim at the middle of the accepted range with the previous slice's density.
  const double guess = lo_.sigma + width_per_pair_ * (target - lo_.below + 0.5 * slack);
  const Shift hi = counter_.place_boundary(lo_, counter_.top(), target, slack, guess);
  const SliceBounds bounds{lo_, hi};
  width_per_pair_ = (hi.sigma - std::max(lo_.sigma, 0.0)) / std::max(1, hi.below - lo_.below);
  lo_ = hi;
  return bounds;
}

}  // namespace pleat
