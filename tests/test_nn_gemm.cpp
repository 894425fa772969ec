// The inference GEMM on both kernels (baseline SSE2 and AVX2+FMA) against a
// double-precision loop, on the shapes the network uses and on strided
// views; the two kernels agree with each other to float rounding.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "nn/gemm.h"
#include "support/kernel_paths.h"

using namespace pleat::nn;

namespace {

struct Shape {
  Index m, k, n;
};

// (batch rows) x (in) x (out) of dense, GRU, attention projection and
// skinning logits, plus edges: one row, one column, depth 1, odd sizes.
const Shape kShapes[] = {{512, 64, 264}, {512, 9, 64}, {8, 384, 1152}, {4096, 64, 31}, {1, 64, 64},
                         {64, 1, 64},    {37, 53, 1},  {3, 3, 3},      {1000, 128, 96}};

MatrixRM random_matrix(Index rows, Index cols, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  MatrixRM m(rows, cols);
  for (Index i = 0; i < m.size(); ++i) m.data()[i] = u(rng);
  return m;
}

TEST(NnGemm, BothKernelsMatchADoubleReferenceOnTheNetworksShapes) {
  const KernelPath initial = kernel_path();
  const auto kernels = pleat_test::runnable_kernel_paths();
  ASSERT_FALSE(kernels.empty());
  std::mt19937 rng(5);
  for (const Shape& s : kShapes) {
    // Strided operands: blocks of wider matrices, as the layers pass them.
    const MatrixRM a_storage = random_matrix(s.m, s.k + 3, rng), b_storage = random_matrix(s.k, s.n + 5, rng);
    const ConstMatrixMap a = view(a_storage.data(), s.m, s.k, s.k + 3);
    const ConstMatrixMap b = view(b_storage.data(), s.k, s.n, s.n + 5);
    Eigen::MatrixXd reference = a.cast<double>() * b.cast<double>();
    std::vector<MatrixRM> results;
    for (KernelPath kernel : kernels) {
      ASSERT_TRUE(set_kernel_path(kernel));
      MatrixRM c_storage = MatrixRM::Constant(s.m, s.n + 2, 7.0f);
      MatrixMap c = view(c_storage.data(), s.m, s.n, s.n + 2);
      gemm(a, b, c);
      // |error| <= k * eps * sum |a||b| bounds float accumulation in any order.
      const Eigen::MatrixXd bound =
          (a.cast<double>().cwiseAbs() * b.cast<double>().cwiseAbs()) * (double(s.k) * 1.2e-7) +
          Eigen::MatrixXd::Constant(s.m, s.n, 1e-30);
      const double worst = ((c.cast<double>() - reference).cwiseAbs().array() / bound.array()).maxCoeff();
      EXPECT_LE(worst, 1.0) << kernel_path_name(kernel) << " " << s.m << "x" << s.k << "x" << s.n;
      EXPECT_TRUE((c_storage.rightCols(2).array() == 7.0f).all()) << "wrote past the view's columns";
      results.push_back(c);
    }
    if (results.size() == 2) {
      EXPECT_LE((results[0] - results[1]).cwiseAbs().maxCoeff(), 1e-5f * float(s.k)) << s.m << "x" << s.k;
    }
  }
  set_kernel_path(initial);
}

TEST(NnGemm, TheBestKernelIsTheDefault) {
  const auto kernels = pleat_test::runnable_kernel_paths();
  EXPECT_EQ(kernel_path(), kernels.back()) << kernel_path_name(kernel_path());
  EXPECT_TRUE(set_kernel_path(KernelPath::baseline)) << "every x86-64 CPU runs the baseline";
  set_kernel_path(kernels.back());
}

}  // namespace
