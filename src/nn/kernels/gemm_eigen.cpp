// Eigen's own GEMM for C = A B on row-major float matrices, compiled once per
// instruction set (nn/kernels/eigen_renamed.h; nn/gemm.cpp picks one at run
// time).
#include "nn/kernels/eigen_renamed.h"
// Only plain declarations from pleat: nothing the linker could merge.
#include "nn/kernels/entry_points.h"

using Matrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using ConstView = Eigen::Map<const Matrix, 0, Eigen::OuterStride<>>;
using View = Eigen::Map<Matrix, 0, Eigen::OuterStride<>>;

namespace pleat::nn::kernels {

void PLEAT_KERNEL_ENTRY(gemm)(const float* a, long a_stride, const float* b, long b_stride, float* c,
                              long c_stride, long m, long k, long n) {
  View(c, m, n, Eigen::OuterStride<>(c_stride)).noalias() =
      ConstView(a, m, k, Eigen::OuterStride<>(a_stride)) * ConstView(b, k, n, Eigen::OuterStride<>(b_stride));
}

}  // namespace pleat::nn::kernels
