// Adamax against updates computed by hand, state round trips, cosine annealing.
#include <gtest/gtest.h>

#include <cmath>

#include "optimizer.h"

using namespace pleat::training;

TEST(TrainingOptimizer, AdamaxMatchesHandComputedSteps) {
  torch::Tensor p = torch::tensor({1.0, -2.0}, torch::kFloat64).requires_grad_(true);
  Adamax opt({p}, 0.1, 0.9, 0.999, 1e-8);
  // L = 3 p0 + p1²: g = (3, 2 p1).
  double m[2] = {0, 0}, u[2] = {0, 0}, x[2] = {1.0, -2.0};
  for (int t = 1; t <= 3; ++t) {
    opt.zero_grad();
    (3 * p[0] + p[1] * p[1]).backward();
    opt.step();
    const double g[2] = {3.0, 2 * x[1]};
    for (int k = 0; k < 2; ++k) {
      m[k] = 0.9 * m[k] + 0.1 * g[k];
      u[k] = std::max(0.999 * u[k], std::abs(g[k]) + 1e-8);
      x[k] -= 0.1 / (1 - std::pow(0.9, t)) * m[k] / u[k];
      EXPECT_NEAR(p[k].item<double>(), x[k], 1e-12) << "step " << t << " entry " << k;
    }
  }
}

TEST(TrainingOptimizer, StateRoundTripResumesExactly) {
  const auto loss = [](const torch::Tensor& p) {
    return (p * p * torch::tensor({1.0, 2.0, 3.0}, torch::kFloat64)).sum();
  };
  const auto steps = [&](Adamax& opt, torch::Tensor& p, int count) {
    for (int i = 0; i < count; ++i) {
      opt.zero_grad();
      loss(p).backward();
      opt.step();
    }
  };
  torch::Tensor straight = torch::tensor({0.5, 0.25, -1.0}, torch::kFloat64).requires_grad_(true);
  Adamax reference({straight}, 0.05);
  steps(reference, straight, 4);
  // 4 steps straight equal 2 steps, a state copy into a fresh optimiser over
  // the same parameter values, and 2 more.
  torch::Tensor p = torch::tensor({0.5, 0.25, -1.0}, torch::kFloat64).requires_grad_(true);
  Adamax first({p}, 0.05);
  steps(first, p, 2);
  torch::Tensor q = p.detach().clone().requires_grad_(true);
  Adamax second({q}, 0.05);
  second.load_state(first.state());
  steps(second, q, 2);
  EXPECT_TRUE(torch::equal(q.detach(), straight.detach()));
  // Without the state the resumed run differs (the check has teeth).
  torch::Tensor r = p.detach().clone().requires_grad_(true);
  Adamax fresh({r}, 0.05);
  steps(fresh, r, 2);
  EXPECT_FALSE(torch::equal(r.detach(), straight.detach()));
}

TEST(TrainingOptimizer, CosineAnnealing) {
  EXPECT_DOUBLE_EQ(cosine_learning_rate(3e-3, 0.0, 0, 100), 3e-3);
  EXPECT_NEAR(cosine_learning_rate(3e-3, 0.0, 50, 100), 1.5e-3, 1e-15);
  EXPECT_NEAR(cosine_learning_rate(3e-3, 1e-4, 100, 100), 1e-4, 1e-15);
  EXPECT_NEAR(cosine_learning_rate(3e-3, 0.0, 25, 100), 3e-3 * 0.5 * (1 + std::cos(3.14159265358979 / 4)),
              1e-12);
}

TEST(TrainingOptimizer, WeightDecayShrinksOnlyTheNamedParametersBeforeTheUpdate) {
  torch::Tensor w = torch::tensor({2.0, -4.0}, torch::kFloat64).requires_grad_(true);
  torch::Tensor b = torch::tensor({2.0, -4.0}, torch::kFloat64).requires_grad_(true);
  Adamax opt({w, b}, 0.1, 0.9, 0.999, 1e-8);
  opt.set_weight_decay(0.5, {w});
  // L = 3 (w0 + b0): one step moves w0 and b0 by the same Adamax update
  // (-0.1 · m / u / (1 - β1) = -0.1, up to ε); w is first shrunk by 1 - 0.1 · 0.5.
  opt.zero_grad();
  (3 * (w[0] + b[0])).backward();
  opt.step();
  EXPECT_NEAR(w[0].item<double>(), 2.0 * 0.95 - 0.1, 1e-9);
  EXPECT_NEAR(b[0].item<double>(), 2.0 - 0.1, 1e-9);
  // A zero gradient still decays: w1 has a gradient tensor (zeros), so it shrinks.
  EXPECT_NEAR(w[1].item<double>(), -4.0 * 0.95, 1e-12);
  EXPECT_NEAR(b[1].item<double>(), -4.0, 1e-12);
}
