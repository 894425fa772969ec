#pragma once
// C = A B for the network's row-major float matrices: the one matrix product
// of inference (dense and GRU layers, the graph-attention projection, the
// skinning logits).
//
// It runs pleat's own builds of Eigen's GEMM (nn/kernels/gemm_eigen.cpp),
// AVX2 + FMA or baseline x86-64 as nn/kernel_path.h chooses. Not BLAS, for
// two measured reasons: OpenBLAS 0.3.21's small-matrix kernels for AVX-512
// CPUs (sgemm_small_kernel_nn_COOPERLAKE, picked on AMD EPYC Zen 4) call
// malloc on every call, which breaks evaluate's promise to allocate nothing;
// and on virtual CPUs it does not recognise, OpenBLAS falls back to SSE3
// kernels unless the host sets OPENBLAS_CORETYPE.
//
// Allocates nothing: Eigen's blocking buffers live on the stack (up to
// 2 x 128 KiB per call).
#include "nn/tensor.h"

namespace pleat::nn {

// c = a * b; shapes must agree (checked by the caller's layer). Neither a nor
// b may alias c.
void gemm(ConstMatrixRef a, ConstMatrixRef b, MatrixRef c);

}  // namespace pleat::nn
