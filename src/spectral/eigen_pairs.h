#pragma once
// The result every band eigensolver returns, and the checks they share.
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace pleat {

// The lowest eigenpairs of a symmetric matrix: values ascending, vectors
// orthonormal columns in the same order.
struct EigenPairs {
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
};

// Largest residual ||A v - lambda v|| over the pairs (0 for none).
double max_residual(const Eigen::SparseMatrix<double>& matrix, const EigenPairs& pairs);

// Residual every solver must reach. L_norm has norm <= 2, so this is ~1e4 ulp
// of the matrix; subspace error at a cut is ~ residual / gap (see bands.h).
constexpr double kResidualTolerance = 1e-11;

// Sorts the pairs by ascending eigenvalue.
void sort_pairs(EigenPairs* pairs);

// Rayleigh-Ritz on span(basis): orthonormalises the basis and returns the
// Ritz pairs of `matrix` in it, ascending. Used to repair orthogonality of
// vectors found by different shifts and to finish the filtered iteration.
EigenPairs rayleigh_ritz(const Eigen::SparseMatrix<double>& matrix, const Eigen::MatrixXd& basis);

}  // namespace pleat
