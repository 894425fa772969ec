#include "nn/gemm.h"

#include "nn/kernel_path.h"
#include "nn/kernels/entry_points.h"

namespace pleat::nn {

void gemm(ConstMatrixRef a, ConstMatrixRef b, MatrixRef c) {
  const auto run = kernel_path() == KernelPath::avx2 ? kernels::gemm_avx2 : kernels::gemm_baseline;
  run(a.data(), a.outerStride(), b.data(), b.outerStride(), c.data(), c.outerStride(), c.rows(), a.cols(),
      c.cols());
}

}  // namespace pleat::nn
