#pragma once
// Lowest eigenpairs by LAPACK dsyevr (MRRR) on the dense matrix: O(N^3) time,
// O(N^2) memory, exact to round-off. The reference for the other solvers.
#include "spectral/eigen_pairs.h"

namespace pleat {

// The `count` lowest eigenpairs of the symmetric `matrix` (1 <= count <= N).
EigenPairs solve_dense(const Eigen::SparseMatrix<double>& matrix, int count);

}  // namespace pleat
