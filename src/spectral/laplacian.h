#pragma once
// The normalised graph Laplacian of a vertex graph (DESIGN §5) and the
// degree scaling used by the random-walk band projection.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "core/mesh.h"

namespace pleat {

// L_norm = I - D^{-1/2} C D^{-1/2} with C the binary adjacency of `graph`.
// Isolated vertices get D^{-1/2} = 0: their row and column are zero, so e_i is
// an eigenvector with eigenvalue 0 (each isolated vertex is its own component).
// The diagonal is always stored (an explicit 0 for isolated vertices) so that
// shifted factorisations see every pivot. Column-major, both triangles stored.
Eigen::SparseMatrix<double> normalized_laplacian(const Csr& graph);

// sqrt(degree) per vertex, 1 for isolated vertices. D^{1/2} 1 spans the null
// space of L_norm on every component (e_i on an isolated vertex), so scaling
// by this vector before projecting keeps constants in the low band exactly.
Eigen::VectorXd sqrt_degree(const Csr& graph);

}  // namespace pleat
