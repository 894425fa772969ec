#pragma once
// Lowest eigenpairs by spectrum slicing: inertia places slice boundaries so
// that each slice holds about kSliceSize eigenvalues, shift-invert Lanczos
// solves each slice at its centre, slices run concurrently (slice_pool.h).
// Memory O(N * count) for the result plus O(N * slice) per worker.
#include "spectral/eigen_pairs.h"

namespace pleat {

// Eigenvalues per slice. Lanczos with full reorthogonalisation is memory-bound
// (three GEMV passes over the N x ncv basis per step), so a slice costs about
// slice^2 and the total about count * slice; factorisations grow with the slice
// count. 20k vertices, one thread: 100 per slice took ~2.4 s a slice, 30-50
// about 0.4-0.8 s, i.e. roughly 40 % less in total (bench noise +-15 %).
constexpr int kSliceSize = 40;

// The `count` lowest eigenpairs of L_norm (1 <= count <= N), on
// default_slice_workers() threads.
EigenPairs solve_slicing(const Eigen::SparseMatrix<double>& laplacian, int count);

// The same with an explicit worker count (>= 1); the result does not depend on it.
EigenPairs solve_slicing(const Eigen::SparseMatrix<double>& laplacian, int count, int workers);

}  // namespace pleat
