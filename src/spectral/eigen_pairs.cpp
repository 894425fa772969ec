#include "spectral/eigen_pairs.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <numeric>
#include <vector>

namespace pleat {

double max_residual(const Eigen::SparseMatrix<double>& matrix, const EigenPairs& pairs) {
  if (pairs.values.size() == 0) return 0.0;
  Eigen::MatrixXd r = matrix * pairs.vectors;
  r -= pairs.vectors * pairs.values.asDiagonal();
  return r.colwise().norm().maxCoeff();
}

void sort_pairs(EigenPairs* pairs) {
  const Eigen::Index n = pairs->values.size();
  std::vector<Eigen::Index> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](Eigen::Index a, Eigen::Index b) { return pairs->values[a] < pairs->values[b]; });
  EigenPairs sorted;
  sorted.values.resize(n);
  sorted.vectors.resize(pairs->vectors.rows(), n);
  for (Eigen::Index i = 0; i < n; ++i) {
    sorted.values[i] = pairs->values[order[static_cast<size_t>(i)]];
    sorted.vectors.col(i) = pairs->vectors.col(order[static_cast<size_t>(i)]);
  }
  *pairs = std::move(sorted);
}

EigenPairs rayleigh_ritz(const Eigen::SparseMatrix<double>& matrix, const Eigen::MatrixXd& basis) {
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(basis);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(basis.rows(), basis.cols());
  Eigen::MatrixXd h = q.transpose() * (matrix * q);
  h = 0.5 * (h + h.transpose()).eval();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(h);
  return {eig.eigenvalues(), q * eig.eigenvectors()};
}

}  // namespace pleat
