#pragma once
// Prelude of every per-instruction-set kernel file in nn/kernels: CMake
// compiles each such file once per PLEAT_KERNEL_VARIANT (baseline, avx2) with
// that build's -m flags, and this header renames Eigen's namespace per build.
// Two copies of the same template instantiations compiled with different
// flags would otherwise collide, and the linker would keep one of them for
// both (an AVX2 kernel on a CPU without AVX2, or the baseline everywhere).
// The test kernel_symbols checks that the AVX2 objects export nothing else.
//
// EIGEN_USE_BLAS is dropped: these kernels must not reach OpenBLAS, whose
// AVX-512 small-matrix kernels call malloc on every call (nn/gemm.h).
#undef EIGEN_USE_BLAS
#define PLEAT_KERNEL_CONCAT_(a, b) a##b
#define PLEAT_KERNEL_CONCAT(a, b) PLEAT_KERNEL_CONCAT_(a, b)
// The entry point `name` of this build: name_baseline or name_avx2.
#define PLEAT_KERNEL_ENTRY(name) PLEAT_KERNEL_CONCAT(name##_, PLEAT_KERNEL_VARIANT)
#define Eigen PLEAT_KERNEL_CONCAT(pleat_eigen_, PLEAT_KERNEL_VARIANT)
#include <Eigen/Core>
