#include "nn/gemm.h"

#include <atomic>

namespace pleat::nn {
namespace kernels {
// nn/kernels/gemm_eigen.cpp, once per instruction set.
void gemm_baseline(const float* a, long a_stride, const float* b, long b_stride, float* c, long c_stride,
                   long m, long k, long n);
void gemm_avx2(const float* a, long a_stride, const float* b, long b_stride, float* c, long c_stride, long m,
               long k, long n);
}  // namespace kernels

namespace {

bool cpu_runs(GemmKernel kernel) {
  if (kernel == GemmKernel::baseline) return true;
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

std::atomic<GemmKernel>& active() {
  static std::atomic<GemmKernel> kernel{cpu_runs(GemmKernel::avx2) ? GemmKernel::avx2 : GemmKernel::baseline};
  return kernel;
}

}  // namespace

void gemm(ConstMatrixRef a, ConstMatrixRef b, MatrixRef c) {
  const auto run = active().load(std::memory_order_relaxed) == GemmKernel::avx2 ? kernels::gemm_avx2
                                                                                : kernels::gemm_baseline;
  run(a.data(), a.outerStride(), b.data(), b.outerStride(), c.data(), c.outerStride(), c.rows(), a.cols(),
      c.cols());
}

GemmKernel gemm_kernel() {
  return active().load();
}

bool set_gemm_kernel(GemmKernel kernel) {
  if (!cpu_runs(kernel)) return false;
  active().store(kernel);
  return true;
}

const char* gemm_kernel_name(GemmKernel kernel) {
  return kernel == GemmKernel::avx2 ? "avx2+fma" : "baseline (SSE2)";
}

}  // namespace pleat::nn
