// The inference GEMM on both kernels (baseline SSE2 and AVX2+FMA) against a
// double-precision loop, on the shapes the network uses and on strided
// views; the two kernels agree with each other to float rounding.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "nn/gemm.h"

using namespace pleat::nn;

namespace {

struct Shape {
  Index m, k, n;
};

// (batch rows) x (in) x (out) of dense, GRU, attention projection and
// skinning logits, plus edges: one row, one column, depth 1, odd sizes.
const Shape kShapes[] = {{512, 64, 264}, {512, 9, 64}, {8, 384, 1152}, {4096, 64, 31}, {1, 64, 64},
                         {64, 1, 64},    {37, 53, 1},  {3, 3, 3},      {1000, 128, 96}};

// The kernels this CPU can run, restoring the default afterwards.
std::vector<GemmKernel> runnable_kernels() {
  const GemmKernel initial = gemm_kernel();
  std::vector<GemmKernel> kernels;
  for (GemmKernel k : {GemmKernel::baseline, GemmKernel::avx2})
    if (set_gemm_kernel(k)) kernels.push_back(k);
  set_gemm_kernel(initial);
  return kernels;
}

MatrixRM random_matrix(Index rows, Index cols, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  MatrixRM m(rows, cols);
  for (Index i = 0; i < m.size(); ++i) m.data()[i] = u(rng);
  return m;
}

TEST(NnGemm, BothKernelsMatchADoubleReferenceOnTheNetworksShapes) {
  const GemmKernel initial = gemm_kernel();
  const auto kernels = runnable_kernels();
  ASSERT_FALSE(kernels.empty());
  std::mt19937 rng(5);
  for (const Shape& s : kShapes) {
    // Strided operands: blocks of wider matrices, as the layers pass them.
    const MatrixRM a_storage = random_matrix(s.m, s.k + 3, rng), b_storage = random_matrix(s.k, s.n + 5, rng);
    const ConstMatrixMap a = view(a_storage.data(), s.m, s.k, s.k + 3);
    const ConstMatrixMap b = view(b_storage.data(), s.k, s.n, s.n + 5);
    Eigen::MatrixXd reference = a.cast<double>() * b.cast<double>();
    std::vector<MatrixRM> results;
    for (GemmKernel kernel : kernels) {
      ASSERT_TRUE(set_gemm_kernel(kernel));
      MatrixRM c_storage = MatrixRM::Constant(s.m, s.n + 2, 7.0f);
      MatrixMap c = view(c_storage.data(), s.m, s.n, s.n + 2);
      gemm(a, b, c);
      // |error| <= k * eps * sum |a||b| bounds float accumulation in any order.
      const Eigen::MatrixXd bound =
          (a.cast<double>().cwiseAbs() * b.cast<double>().cwiseAbs()) * (double(s.k) * 1.2e-7) +
          Eigen::MatrixXd::Constant(s.m, s.n, 1e-30);
      const double worst = ((c.cast<double>() - reference).cwiseAbs().array() / bound.array()).maxCoeff();
      EXPECT_LE(worst, 1.0) << gemm_kernel_name(kernel) << " " << s.m << "x" << s.k << "x" << s.n;
      EXPECT_TRUE((c_storage.rightCols(2).array() == 7.0f).all()) << "wrote past the view's columns";
      results.push_back(c);
    }
    if (results.size() == 2) {
      EXPECT_LE((results[0] - results[1]).cwiseAbs().maxCoeff(), 1e-5f * float(s.k)) << s.m << "x" << s.k;
    }
  }
  set_gemm_kernel(initial);
}

TEST(NnGemm, TheBestKernelIsTheDefault) {
  const auto kernels = runnable_kernels();
  EXPECT_EQ(gemm_kernel(), kernels.back()) << gemm_kernel_name(gemm_kernel());
  EXPECT_TRUE(set_gemm_kernel(GemmKernel::baseline)) << "every x86-64 CPU runs the baseline";
  set_gemm_kernel(kernels.back());
}

}  // namespace
