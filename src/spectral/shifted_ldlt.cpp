#include "spectral/shifted_ldlt.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "core/error.h"

namespace pleat {

ShiftedLdlt::ShiftedLdlt(const Eigen::SparseMatrix<double>& matrix)
    : upper_(matrix.triangularView<Eigen::Upper>()) {
  upper_.makeCompressed();
  cholmod_start(&common_);
  common_.print = 0;                        // failures become pleat::Error, not stderr
  common_.supernodal = CHOLMOD_SIMPLICIAL;  // simplicial keeps D explicit for inertia
  common_.final_ll = false;                 // LDL^T: indefinite shifts are allowed
  std::memset(&a_, 0, sizeof(a_));
  a_.nrow = a_.ncol = static_cast<size_t>(upper_.rows());
  a_.nzmax = static_cast<size_t>(upper_.nonZeros());
  a_.p = upper_.outerIndexPtr();
  a_.i = upper_.innerIndexPtr();
  a_.x = upper_.valuePtr();
  a_.stype = 1;  // upper triangle holds the symmetric matrix
  a_.itype = CHOLMOD_INT;
  a_.xtype = CHOLMOD_REAL;
  a_.dtype = CHOLMOD_DOUBLE;
  a_.sorted = 1;
  a_.packed = 1;
  factor_ = cholmod_analyze(&a_, &common_);
  if (factor_ == nullptr)
    fail(PLEAT_ERROR_NUMERICAL, "CHOLMOD analysis failed (status " + std::to_string(common_.status) + ")");
}

ShiftedLdlt::~ShiftedLdlt() {
  cholmod_free_dense(&x_, &common_);
  cholmod_free_dense(&y_, &common_);
  cholmod_free_dense(&e_, &common_);
  cholmod_free_factor(&factor_, &common_);
  cholmod_finish(&common_);
}

void ShiftedLdlt::factorize(double sigma) {
  double beta[2] = {-sigma, 0.0};
  sigma_ = sigma;
  factorized_ = cholmod_factorize_p(&a_, beta, nullptr, 0, factor_, &common_) &&
                common_.status >= CHOLMOD_OK && !factor_->is_ll && !factor_->is_super;
  if (!factorized_ && common_.status != CHOLMOD_NOT_POSDEF)
    fail(PLEAT_ERROR_NUMERICAL, "CHOLMOD LDL^T of L - sigma I failed at sigma = " + std::to_string(sigma) +
                                    " (status " + std::to_string(common_.status) + ")");
}

int ShiftedLdlt::negative_pivots() const {
  // Simplicial LDL^T stores D_j as the first entry of column j.
  const auto* p = static_cast<const int*>(factor_->p);
  const auto* x = static_cast<const double*>(factor_->x);
  int negative = 0;
  for (size_t j = 0; j < factor_->n; ++j) negative += x[p[j]] < 0.0;
  return negative;
}

double ShiftedLdlt::min_abs_pivot() const {
  // A failed factorisation stopped at a zero pivot.
  if (!factorized_) return 0.0;
  const auto* p = static_cast<const int*>(factor_->p);
  const auto* x = static_cast<const double*>(factor_->x);
  double smallest = std::numeric_limits<double>::infinity();
  for (size_t j = 0; j < factor_->n; ++j) smallest = std::min(smallest, std::abs(x[p[j]]));
  return smallest;
}

void ShiftedLdlt::solve(const double* x, double* y) const {
  cholmod_dense b;
  std::memset(&b, 0, sizeof(b));
  b.nrow = b.nzmax = b.d = factor_->n;
  b.ncol = 1;
  b.x = const_cast<double*>(x);  // CHOLMOD only reads B
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  if (!cholmod_solve2(CHOLMOD_A, factor_, &b, nullptr, &x_, nullptr, &y_, &e_, &common_))
    fail(PLEAT_ERROR_NUMERICAL, "CHOLMOD solve failed at sigma = " + std::to_string(sigma_));
  std::memcpy(y, x_->x, factor_->n * sizeof(double));
}

}  // namespace pleat
