#pragma once
// Picks and runs one of the three eigensolvers for the lowest eigenpairs of
// L_norm. All three return the same pairs (to round-off, up to the basis
// inside repeated eigenvalues).
#include "spectral/band_options.h"
#include "spectral/eigen_pairs.h"

namespace pleat {

// `automatic` uses the dense solver below this many vertices: dsyevr is
// O(N^3) but exact and fast at this size, and needs N^2 doubles (72 MB here).
constexpr int kDenseSolverLimit = 3000;

// The solver `automatic` stands for at this size (others pass through).
SolverKind resolve_solver(SolverKind requested, int vertex_count);

// The `count` lowest eigenpairs of `laplacian` with the given (resolved) solver.
// Throws PLEAT_ERROR_NUMERICAL on failure or a non-finite result.
EigenPairs solve_lowest(const Eigen::SparseMatrix<double>& laplacian, int count, SolverKind kind);

}  // namespace pleat
