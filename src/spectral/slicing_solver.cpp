#include "spectral/slicing_solver.h"

#include "spectral/blas_threads.h"
#include "spectral/slice_planner.h"
#include "spectral/slice_pool.h"
#include "spectral/slicer.h"

namespace pleat {

EigenPairs solve_slicing(const Eigen::SparseMatrix<double>& laplacian, int count) {
  return solve_slicing(laplacian, count, default_slice_workers());
}

EigenPairs solve_slicing(const Eigen::SparseMatrix<double>& laplacian, int count, int workers) {
  const SingleThreadedBlas blas;  // the slices are the parallelism
  SlicePlanner planner(laplacian, count, kSliceSize);
  const SolvedSlices solved = solve_slices(laplacian, &planner, workers);
  EigenPairs pairs = merge_slices(laplacian, solved.slices, solved.boundaries);
  truncate_pairs(&pairs, count);
  return pairs;
}

}  // namespace pleat
