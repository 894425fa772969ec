#pragma once
// Solves the slices of a SlicePlanner concurrently. The calling thread places
// boundaries (cheap: about one factorisation per slice) while `workers`
// threads solve the slices already placed (Lanczos: the bulk of the time).
// CHOLMOD's workspace is not thread-safe, so every worker owns a Slicer.
#include <Eigen/SparseCore>
#include <vector>

#include "spectral/eigen_pairs.h"
#include "spectral/slice_planner.h"

namespace pleat {

struct SolvedSlices {
  std::vector<EigenPairs> slices;  // in slice order
  std::vector<double> boundaries;  // between consecutive slices
};

// A worker count for this machine: one per hardware thread, at most 8.
int default_slice_workers();

// Results do not depend on `workers` (>= 1): boundaries come from the planner
// alone, every slice starts Lanczos from the same seed, and slices are kept in
// slice order. The first failing slice's error is rethrown.
SolvedSlices solve_slices(const Eigen::SparseMatrix<double>& laplacian, SlicePlanner* planner, int workers);

}  // namespace pleat
