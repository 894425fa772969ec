#pragma once
// CHOLMOD simplicial LDL^T of A - sigma I for a fixed sparsity pattern: the
// shift-invert operator of the slicing solver and, by Sylvester's law of
// inertia, an eigenvalue counter (negative pivots of D = eigenvalues < sigma).
#include <cholmod.h>

#include <Eigen/SparseCore>

namespace pleat {

class ShiftedLdlt {
 public:
  // Analyses the pattern once (AMD ordering); `matrix` must be symmetric.
  explicit ShiftedLdlt(const Eigen::SparseMatrix<double>& matrix);
  ~ShiftedLdlt();
  ShiftedLdlt(const ShiftedLdlt&) = delete;
  ShiftedLdlt& operator=(const ShiftedLdlt&) = delete;

  // Factorises A - sigma I. Without pivoting an indefinite LDL^T can meet a
  // (near-)zero pivot when sigma is (near) an eigenvalue; the result is then
  // unusable, so callers check min_abs_pivot() and move sigma.
  void factorize(double sigma);
  double sigma() const { return sigma_; }
  int negative_pivots() const;
  double min_abs_pivot() const;

  // y = (A - sigma I)^{-1} x for the last factorised sigma.
  void solve(const double* x, double* y) const;
  int rows() const { return static_cast<int>(upper_.rows()); }

 private:
  Eigen::SparseMatrix<double> upper_;  // the storage cholmod_sparse A_ points into
  mutable cholmod_common common_;
  cholmod_sparse a_;
  cholmod_factor* factor_ = nullptr;
  mutable cholmod_dense* x_ = nullptr;  // solve2 workspaces, reused across solves
  mutable cholmod_dense* y_ = nullptr;
  mutable cholmod_dense* e_ = nullptr;
  double sigma_ = 0.0;
  bool factorized_ = false;
};

}  // namespace pleat
