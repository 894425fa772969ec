#include "spectral/blas_threads.h"

#include <mutex>

// OpenBLAS's own controls (cblas.h declares them, but including it would
// clash with Eigen's BLAS prototypes).
extern "C" {
int openblas_get_num_threads(void);
void openblas_set_num_threads(int threads);
}

namespace pleat {
namespace {

// OpenBLAS's thread count is process-wide, and scopes on different threads
// (concurrent instances, a prepare beside an evaluate) overlap in any order:
// the first scope in saves the setting and the last one out restores it.
std::mutex blas_mutex;
int blas_scopes = 0;
int blas_saved_threads = 0;

}  // namespace

SingleThreadedBlas::SingleThreadedBlas() {
  const std::lock_guard<std::mutex> lock(blas_mutex);
  if (blas_scopes++ == 0) {
    blas_saved_threads = openblas_get_num_threads();
    openblas_set_num_threads(1);
  }
}

SingleThreadedBlas::~SingleThreadedBlas() {
  const std::lock_guard<std::mutex> lock(blas_mutex);
  if (--blas_scopes == 0) openblas_set_num_threads(blas_saved_threads);
}

}  // namespace pleat
