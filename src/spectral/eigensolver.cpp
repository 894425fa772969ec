#include "spectral/eigensolver.h"

#include "core/error.h"
#include "spectral/dense_solver.h"
#include "spectral/hybrid_solver.h"
#include "spectral/slicing_solver.h"

namespace pleat {

SolverKind resolve_solver(SolverKind requested, int vertex_count) {
  if (requested != SolverKind::automatic) return requested;
  return vertex_count < kDenseSolverLimit ? SolverKind::dense : SolverKind::slicing;
}

EigenPairs solve_lowest(const Eigen::SparseMatrix<double>& laplacian, int count, SolverKind kind) {
  EigenPairs pairs;
  switch (resolve_solver(kind, static_cast<int>(laplacian.rows()))) {
    case SolverKind::dense: pairs = solve_dense(laplacian, count); break;
    case SolverKind::slicing: pairs = solve_slicing(laplacian, count); break;
    case SolverKind::hybrid: pairs = solve_hybrid(laplacian, count); break;
    case SolverKind::automatic: fail(PLEAT_ERROR_INTERNAL, "unresolved automatic solver");
  }
  if (pairs.values.size() != count || !pairs.values.allFinite() || !pairs.vectors.allFinite())
    fail(PLEAT_ERROR_NUMERICAL, "eigensolver returned a non-finite or incomplete result");
  return pairs;
}

}  // namespace pleat
