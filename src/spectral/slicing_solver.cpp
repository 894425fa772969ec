#include "spectral/slicing_solver.h"

#include <algorithm>
#include <string>
#include <vector>

#include "spectral/slicer.h"

namespace pleat {

EigenPairs solve_slicing(const Eigen::SparseMatrix<double>& laplacian, int count) {
  Slicer slicer(laplacian);
  Shift lo = slicer.count_below(kShiftBelowSpectrum);
  std::vector<EigenPairs> slices;
  std::vector<double> boundaries;
  double width_per_pair = 0.0;  // from the previous slice: a first guess for the next boundary
  while (lo.below < count) {
    const int remaining = count - lo.below;
    // A short tail joins the last slice rather than forming a tiny one.
    const int target = remaining <= kSliceSize * 3 / 2 ? count : lo.below + kSliceSize;
    const double guess = lo.sigma + width_per_pair * (target - lo.below + kSliceSize / 8);
    const Shift hi = slicer.place_boundary(lo, slicer.top(), target, kSliceSize / 4, guess);
    const std::string label = "slice " + std::to_string(slices.size());
    if (!slices.empty()) boundaries.push_back(lo.sigma);
    slices.push_back(slicer.solve_interval(lo, hi, label));
    width_per_pair = (hi.sigma - std::max(lo.sigma, 0.0)) / std::max(1, hi.below - lo.below);
    lo = hi;
  }
  EigenPairs pairs = merge_slices(laplacian, slices, boundaries);
  truncate_pairs(&pairs, count);
  return pairs;
}

}  // namespace pleat
