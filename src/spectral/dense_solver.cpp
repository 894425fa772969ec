#include "spectral/dense_solver.h"

#include <cstddef>
#include <string>
#include <vector>

#include "core/error.h"

// LAPACK from OpenBLAS (gfortran ABI: hidden string lengths at the end).
extern "C" void dsyevr_(const char* jobz, const char* range, const char* uplo, const int* n, double* a,
                        const int* lda, const double* vl, const double* vu, const int* il, const int* iu,
                        const double* abstol, int* m, double* w, double* z, const int* ldz, int* isuppz,
                        double* work, const int* lwork, int* iwork, const int* liwork, int* info,
                        size_t jobz_len, size_t range_len, size_t uplo_len);

namespace pleat {

EigenPairs solve_dense(const Eigen::SparseMatrix<double>& matrix, int count) {
  const int n = static_cast<int>(matrix.rows());
  Eigen::MatrixXd a = Eigen::MatrixXd(matrix);
  EigenPairs pairs;
  pairs.values.resize(n);  // dsyevr writes all N slots of w
  pairs.vectors.resize(n, count);
  std::vector<int> isuppz(2 * static_cast<size_t>(count));
  const double unused = 0.0, abstol = 0.0;
  const int il = 1, iu = count;
  int found = 0, info = 0, lwork = -1, liwork = -1, iwork_query = 0;
  double work_query = 0.0;
  auto call = [&](double* work, int* iwork) {
    dsyevr_("V", "I", "L", &n, a.data(), &n, &unused, &unused, &il, &iu, &abstol, &found, pairs.values.data(),
            pairs.vectors.data(), &n, isuppz.data(), work, &lwork, iwork, &liwork, &info, 1, 1, 1);
  };
  call(&work_query, &iwork_query);
  lwork = static_cast<int>(work_query);
  liwork = iwork_query;
  std::vector<double> work(static_cast<size_t>(lwork));
  std::vector<int> iwork(static_cast<size_t>(liwork));
  call(work.data(), iwork.data());
  if (info != 0 || found != count)
    fail(PLEAT_ERROR_NUMERICAL, "dense eigensolver (dsyevr) failed: info " + std::to_string(info) + ", " +
                                    std::to_string(found) + " of " + std::to_string(count) + " eigenpairs");
  pairs.values.conservativeResize(count);
  return pairs;
}

}  // namespace pleat
