#pragma once
// C = A B for the network's row-major float matrices: the one matrix product
// of inference (dense and GRU layers, the graph-attention projection, the
// skinning logits).
//
// It runs pleat's own builds of Eigen's GEMM, chosen once per process from
// the CPU: AVX2 + FMA where the CPU has both, else baseline x86-64 (SSE2).
// Not BLAS, for two measured reasons: OpenBLAS 0.3.21's small-matrix kernels
// for AVX-512 CPUs (sgemm_small_kernel_nn_COOPERLAKE, picked on AMD EPYC
// Zen 4) call malloc on every call, which breaks evaluate's promise to
// allocate nothing; and on virtual CPUs it does not recognise, OpenBLAS falls
// back to SSE3 kernels unless the host sets OPENBLAS_CORETYPE.
//
// Allocates nothing: Eigen's blocking buffers live on the stack (up to
// 2 x 128 KiB per call).
#include "nn/tensor.h"

namespace pleat::nn {

enum class GemmKernel { baseline, avx2 };

// c = a * b; shapes must agree (checked by the caller's layer). Neither a nor
// b may alias c.
void gemm(ConstMatrixRef a, ConstMatrixRef b, MatrixRef c);

// The kernel gemm() uses: the best the CPU runs, unless set.
GemmKernel gemm_kernel();
// For tests and benchmarks: forces a kernel (false, and no change, when the
// CPU cannot run it). Not thread-safe with running products.
bool set_gemm_kernel(GemmKernel kernel);
const char* gemm_kernel_name(GemmKernel kernel);  // "baseline (SSE2)", "avx2+fma"

}  // namespace pleat::nn
