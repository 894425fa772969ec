#pragma once
// Places spectrum-slicing boundaries one after another, from the bottom of
// the spectrum up to the requested count. Depends only on inertia counts, never
// on solved eigenpairs, so the boundaries (and therefore every slice's result)
// are the same whichever worker later solves which slice.
#include <Eigen/SparseCore>
#include <optional>

#include "spectral/slicer.h"

namespace pleat {

struct SliceBounds {
  Shift lo;
  Shift hi;
};

class SlicePlanner {
 public:
  // `slice_size`: eigenvalues wanted per slice (accepted: half to 1.5 times).
  SlicePlanner(const Eigen::SparseMatrix<double>& laplacian, int count, int slice_size);

  // The next slice above the previous one, or nothing once `count` is covered.
  std::optional<SliceBounds> next();

 private:
  Slicer counter_;  // only counts; its factorisations never serve a solve
  int count_;
  int slice_size_;
  Shift lo_;
  double width_per_pair_ = 0.0;  // of the previous slice: the next boundary's first guess
};

}  // namespace pleat
