#include "spectral/blas_threads.h"

// OpenBLAS's own controls (cblas.h declares them, but including it would
// clash with Eigen's BLAS prototypes).
extern "C" {
int openblas_get_num_threads(void);
void openblas_set_num_threads(int threads);
}

namespace pleat {

SingleThreadedBlas::SingleThreadedBlas() : previous_(openblas_get_num_threads()) {
  openblas_set_num_threads(1);
}

SingleThreadedBlas::~SingleThreadedBlas() {
  openblas_set_num_threads(previous_);
}

}  // namespace pleat
