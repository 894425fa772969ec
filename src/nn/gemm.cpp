#include "nn/gemm.h"

#include "nn/kernel_path.h"

namespace pleat::nn {
namespace kernels {
// nn/kernels/gemm_eigen.cpp, once per instruction set.
void gemm_baseline(const float* a, long a_stride, const float* b, long b_stride, float* c, long c_stride,
                   long m, long k, long n);
void gemm_avx2(const float* a, long a_stride, const float* b, long b_stride, float* c, long c_stride, long m,
               long k, long n);
}  // namespace kernels

void gemm(ConstMatrixRef a, ConstMatrixRef b, MatrixRef c) {
  const auto run = kernel_path() == KernelPath::avx2 ? kernels::gemm_avx2 : kernels::gemm_baseline;
  run(a.data(), a.outerStride(), b.data(), b.outerStride(), c.data(), c.outerStride(), c.rows(), a.cols(),
      c.cols());
}

}  // namespace pleat::nn
