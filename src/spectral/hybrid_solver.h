#pragma once
// Lowest eigenpairs for large N: one shift-invert slice gives the exact
// eigenpairs in a window [a, b) at the top of the wanted range (where the band
// cut and its gap live); a Jackson-Chebyshev filtered subspace iteration,
// deflated against the window, gives every eigenpair below a. The filter
// only has to separate [0, a] from [b, 2], so no factorisation is needed for
// the bulk of the spectrum. See docs/spectral.md.
#include "spectral/eigen_pairs.h"

namespace pleat {

// The `count` lowest eigenpairs of L_norm (1 <= count <= N).
EigenPairs solve_hybrid(const Eigen::SparseMatrix<double>& laplacian, int count);

}  // namespace pleat
