#include "spectral/laplacian.h"

#include <cmath>
#include <vector>

namespace pleat {

Eigen::VectorXd sqrt_degree(const Csr& graph) {
  const int32_t n = graph.vertex_count();
  Eigen::VectorXd s(n);
  for (int32_t v = 0; v < n; ++v) {
    const int32_t d = graph.degree(v);
    s[v] = d > 0 ? std::sqrt(static_cast<double>(d)) : 1.0;
  }
  return s;
}

Eigen::SparseMatrix<double> normalized_laplacian(const Csr& graph) {
  const int32_t n = graph.vertex_count();
  Eigen::VectorXd inv_sqrt(n);
  for (int32_t v = 0; v < n; ++v) {
    const int32_t d = graph.degree(v);
    inv_sqrt[v] = d > 0 ? 1.0 / std::sqrt(static_cast<double>(d)) : 0.0;
  }
  // The graph is symmetric with sorted rows, so its CSR is also the CSC of L;
  // fill the columns directly, inserting the diagonal at its sorted place.
  Eigen::SparseMatrix<double> laplacian(n, n);
  laplacian.reserve(Eigen::VectorXi::Constant(n, 1) +
                    Eigen::Map<const Eigen::VectorXi>(graph.offsets.data() + 1, n) -
                    Eigen::Map<const Eigen::VectorXi>(graph.offsets.data(), n));
  for (int32_t col = 0; col < n; ++col) {
    const double diagonal = graph.degree(col) > 0 ? 1.0 : 0.0;
    bool diagonal_done = false;
    for (int32_t k = graph.offsets[col]; k < graph.offsets[col + 1]; ++k) {
      const int32_t row = graph.indices[k];
      if (!diagonal_done && row > col) {
        laplacian.insert(col, col) = diagonal;
        diagonal_done = true;
      }
      laplacian.insert(row, col) = -inv_sqrt[row] * inv_sqrt[col];
    }
    if (!diagonal_done) laplacian.insert(col, col) = diagonal;
  }
  laplacian.makeCompressed();
  return laplacian;
}

}  // namespace pleat
