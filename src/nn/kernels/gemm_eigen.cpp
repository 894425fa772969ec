// Eigen's own GEMM for C = A B on row-major float matrices, compiled once per
// instruction set (CMake builds this file as pleat_gemm_baseline and
// pleat_gemm_avx2; nn/gemm.cpp picks one at run time).
//
// Each build renames the Eigen namespace: two copies of the same template
// instantiations compiled with different -m flags would otherwise collide,
// and the linker would keep one of them for both (an AVX2 kernel on a CPU
// without AVX2, or the baseline everywhere). No other header of pleat may be
// included here for the same reason; the interface is plain pointers.
//
// EIGEN_USE_BLAS is dropped: these products must not reach OpenBLAS, whose
// AVX-512 small-matrix kernels call malloc on every call (nn/gemm.h).
#undef EIGEN_USE_BLAS
#define Eigen PLEAT_GEMM_CONCAT(pleat_eigen_, PLEAT_GEMM_VARIANT)
#define PLEAT_GEMM_CONCAT(a, b) PLEAT_GEMM_CONCAT_(a, b)
#define PLEAT_GEMM_CONCAT_(a, b) a##b
#include <Eigen/Core>

using Matrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using ConstView = Eigen::Map<const Matrix, 0, Eigen::OuterStride<>>;
using View = Eigen::Map<Matrix, 0, Eigen::OuterStride<>>;

namespace pleat::nn::kernels {

void PLEAT_GEMM_CONCAT(gemm_, PLEAT_GEMM_VARIANT)(const float* a, long a_stride, const float* b,
                                                  long b_stride, float* c, long c_stride, long m, long k,
                                                  long n) {
  View(c, m, n, Eigen::OuterStride<>(c_stride)).noalias() =
      ConstView(a, m, k, Eigen::OuterStride<>(a_stride)) * ConstView(b, k, n, Eigen::OuterStride<>(b_stride));
}

}  // namespace pleat::nn::kernels
