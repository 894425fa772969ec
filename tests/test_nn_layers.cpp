// Activations, Dense, MLP and GRU against naive double-precision loops
// written from the formulas (PyTorch conventions for the GRU).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "nn/activation.h"
#include "nn/dense.h"
#include "nn/gru.h"
#include "nn/mlp.h"
#include "support/expect_error.h"
#include "support/kernel_paths.h"

using namespace pleat;
using namespace pleat::nn;

namespace {

MatrixRM random_matrix(Index r, Index c, std::mt19937& rng, float scale = 1.0f) {
  std::uniform_real_distribution<float> u(-scale, scale);
  MatrixRM m(r, c);
  for (Index i = 0; i < m.size(); ++i) m.data()[i] = u(rng);
  return m;
}

double act_ref(const Activation& a, double x) {
  switch (a.kind) {
    case ActivationKind::identity: return x;
    case ActivationKind::tanh: return std::tanh(x);
    case ActivationKind::relu: return x > 0 ? x : 0;
    case ActivationKind::leaky_relu: return x > 0 ? x : a.parameter * x;
    case ActivationKind::elu: return x > 0 ? x : a.parameter * (std::exp(x) - 1);
  }
  return x;
}

using pleat_test::expect_error_all;

}  // namespace

// On both kernel paths; 34 values, so the SIMD tails (4 and 8 lanes) run too.
TEST(NnActivation, MatchesFormulas) {
  std::vector<float> xs;
  for (float x = -6.0f; x <= 6.0f; x += 0.37f) xs.push_back(x);
  xs.push_back(0.0f);
  pleat_test::for_each_kernel_path([&](KernelPath) {
    for (Activation a : {Activation::identity(), Activation::tanh(), Activation::relu(),
                         Activation::leaky_relu(0.2f), Activation::elu(0.7f)}) {
      std::vector<float> y = xs;
      apply_activation(a, y.data(), static_cast<Index>(y.size()));
      for (size_t k = 0; k < xs.size(); ++k)
        EXPECT_NEAR(y[k], act_ref(a, xs[k]), 2e-6) << static_cast<int>(a.kind) << " x=" << xs[k];
    }
  });
}

TEST(NnDense, MatchesNaiveAndNamesBadShapes) {
  std::mt19937 rng(2);
  Dense d;
  d.name = "head";
  d.weight = random_matrix(7, 5, rng);
  d.bias = random_matrix(1, 5, rng);
  const MatrixRM x = random_matrix(11, 7, rng);
  MatrixRM y(11, 5);
  dense_forward(d, x, Activation::elu(1.0f), y);
  for (int r = 0; r < 11; ++r)
    for (int c = 0; c < 5; ++c) {
      double s = d.bias[c];
      for (int k = 0; k < 7; ++k) s += double(x(r, k)) * d.weight(k, c);
      EXPECT_NEAR(y(r, c), act_ref(Activation::elu(1.0f), s), 1e-5);
    }
  MatrixRM bad(11, 4);
  expect_error_all([&] { dense_forward(d, x, Activation::tanh(), bad); }, PLEAT_ERROR_INVALID_ARGUMENT,
                   {"head", "output y is 11x4", "expected 11x5"});
  expect_error_all([&] { dense_forward(d, MatrixRM::Zero(3, 6), Activation::tanh(), y); },
                   PLEAT_ERROR_INVALID_ARGUMENT, {"input x is 3x6", "expected anyx7"});
}

TEST(NnMlp, MatchesNaiveReference) {
  std::mt19937 rng(4);
  Mlp mlp;
  mlp.name = "body_encoder";
  const int widths[] = {10, 128, 256, 128};
  for (int l = 0; l < 3; ++l) {
    Dense d;
    d.weight = random_matrix(widths[l], widths[l + 1], rng, 1.0f / std::sqrt(float(widths[l])));
    d.bias = random_matrix(1, widths[l + 1], rng, 0.1f);
    mlp.layers.push_back(d);
  }
  mlp.hidden_activation = Activation::tanh();
  mlp.output_activation = Activation::identity();
  mlp.validate();
  const MatrixRM x = random_matrix(37, 10, rng);
  MlpWorkspace ws;
  ws.reserve(mlp, 37);
  MatrixRM y(37, 128);
  mlp_forward(mlp, x, y, ws);
  for (int r = 0; r < 37; ++r) {
    std::vector<double> h(x.row(r).data(), x.row(r).data() + 10);
    for (int l = 0; l < 3; ++l) {
      std::vector<double> next(static_cast<size_t>(widths[l + 1]));
      for (int c = 0; c < widths[l + 1]; ++c) {
        double s = mlp.layers[l].bias[c];
        for (int k = 0; k < widths[l]; ++k) s += h[k] * mlp.layers[l].weight(k, c);
        next[c] = l < 2 ? std::tanh(s) : s;
      }
      h = next;
    }
    for (int c = 0; c < 128; ++c) ASSERT_NEAR(y(r, c), h[c], 2e-5) << r << "," << c;
  }
  // Fewer rows than reserved is fine; more is an error naming the workspace.
  MatrixRM y5(5, 128);
  mlp_forward(mlp, x.topRows(5), y5, ws);
  for (Index k = 0; k < y5.size(); ++k) ASSERT_NEAR(y5.data()[k], y.topRows(5).eval().data()[k], 1e-6);
  MatrixRM big_x = random_matrix(40, 10, rng), big_y(40, 128);
  expect_error_all([&] { mlp_forward(mlp, big_x, big_y, ws); }, PLEAT_ERROR_INVALID_ARGUMENT,
                   {"body_encoder", "MlpWorkspace"});
  Mlp broken = mlp;
  broken.layers[1].weight = MatrixRM::Zero(100, 256);
  expect_error_all([&] { broken.validate(); }, PLEAT_ERROR_INVALID_ARGUMENT,
                   {"body_encoder", "layer 1", "100 rows", "expected 128"});
}

namespace {

// PyTorch-layout GRU parameters (weight_ih_l{k}: 3H x in, rows [r; z; n]).
struct TorchGru {
  std::vector<MatrixRM> w_ih, w_hh;
  std::vector<RowVector> b_ih, b_hh;
};

TorchGru random_torch_gru(int layers, int in, int hidden, std::mt19937& rng) {
  TorchGru t;
  const float k = 1.0f / std::sqrt(float(hidden));
  for (int l = 0; l < layers; ++l) {
    t.w_ih.push_back(random_matrix(3 * hidden, l == 0 ? in : hidden, rng, k));
    t.w_hh.push_back(random_matrix(3 * hidden, hidden, rng, k));
    t.b_ih.push_back(random_matrix(1, 3 * hidden, rng, k));
    t.b_hh.push_back(random_matrix(1, 3 * hidden, rng, k));
  }
  return t;
}

Gru to_gru(const TorchGru& t) {
  Gru g;
  g.name = "motion_encoder";
  for (size_t l = 0; l < t.w_ih.size(); ++l)
    g.layers.push_back({t.w_ih[l].transpose(), t.w_hh[l].transpose(), t.b_ih[l], t.b_hh[l]});
  return g;
}

// One sequence, zero initial state; returns the last layer's final hidden state.
std::vector<double> gru_reference(const TorchGru& t, const std::vector<std::vector<double>>& xs, int hidden) {
  const size_t layers = t.w_ih.size();
  std::vector<std::vector<double>> h(layers, std::vector<double>(hidden, 0.0));
  auto sigmoid = [](double v) { return 1.0 / (1.0 + std::exp(-v)); };
  for (const auto& x_t : xs) {
    std::vector<double> input = x_t;
    for (size_t l = 0; l < layers; ++l) {
      std::vector<double> next(hidden);
      for (int u = 0; u < hidden; ++u) {
        double gi[3], gh[3];
        for (int g = 0; g < 3; ++g) {
          gi[g] = t.b_ih[l][g * hidden + u];
          gh[g] = t.b_hh[l][g * hidden + u];
          for (size_t k = 0; k < input.size(); ++k) gi[g] += double(t.w_ih[l](g * hidden + u, k)) * input[k];
          for (int k = 0; k < hidden; ++k) gh[g] += double(t.w_hh[l](g * hidden + u, k)) * h[l][k];
        }
        const double r = sigmoid(gi[0] + gh[0]);
        const double z = sigmoid(gi[1] + gh[1]);
        const double n = std::tanh(gi[2] + r * gh[2]);
        next[u] = (1 - z) * n + z * h[l][u];
      }
      h[l] = next;
      input = next;
    }
  }
  return h.back();
}

}  // namespace

TEST(NnGru, WindowMatchesNaiveTorchReference) {
  std::mt19937 rng(8);
  const int layers = 3, in = 19, hidden = 32, steps = 8, batch = 3;
  const TorchGru t = random_torch_gru(layers, in, hidden, rng);
  const Gru gru = to_gru(t);
  gru.validate();
  const MatrixRM x = random_matrix(steps * batch, in, rng, 2.0f);  // time-major
  GruWorkspace ws;
  ws.reserve(gru, batch);
  MatrixRM out(batch, hidden);
  gru_window(gru, x, steps, out, ws);
  for (int b = 0; b < batch; ++b) {
    std::vector<std::vector<double>> xs;
    for (int s = 0; s < steps; ++s)
      xs.emplace_back(x.row(s * batch + b).data(), x.row(s * batch + b).data() + in);
    const std::vector<double> ref = gru_reference(t, xs, hidden);
    for (int u = 0; u < hidden; ++u) ASSERT_NEAR(out(b, u), ref[u], 2e-6) << "sample " << b << " unit " << u;
  }
}

TEST(NnGru, StreamingEqualsWindowBitForBit) {
  std::mt19937 rng(12);
  const int layers = 3, in = 11, hidden = 128, steps = 8;
  const Gru gru = to_gru(random_torch_gru(layers, in, hidden, rng));
  for (int batch : {1, 4}) {
    const MatrixRM x = random_matrix(steps * batch, in, rng, 1.5f);
    GruWorkspace ws;
    ws.reserve(gru, batch);
    MatrixRM window(batch, hidden);
    gru_window(gru, x, steps, window, ws);
    MatrixRM state = MatrixRM::Zero(layers * batch, hidden);
    for (int s = 0; s < steps; ++s) gru_step(gru, x.middleRows(s * batch, batch), state, ws);
    const MatrixRM last = state.bottomRows(batch);
    for (Index k = 0; k < last.size(); ++k) ASSERT_EQ(last.data()[k], window.data()[k]) << "batch " << batch;
    // Carrying the state over more calls keeps going from there.
    MatrixRM longer = random_matrix((steps + 2) * batch, in, rng);
    longer.topRows(steps * batch) = x;
    MatrixRM window10(batch, hidden);
    gru_window(gru, longer, steps + 2, window10, ws);
    for (int s = steps; s < steps + 2; ++s) gru_step(gru, longer.middleRows(s * batch, batch), state, ws);
    for (Index k = 0; k < window10.size(); ++k)
      ASSERT_EQ(state.bottomRows(batch).eval().data()[k], window10.data()[k]);
  }
}

TEST(NnGru, ShapeErrorsNameTheTensor) {
  std::mt19937 rng(1);
  Gru gru = to_gru(random_torch_gru(2, 5, 8, rng));
  GruWorkspace ws;
  ws.reserve(gru, 2);
  MatrixRM state = MatrixRM::Zero(4, 8), out(2, 8);
  expect_error_all([&] { gru_step(gru, MatrixRM::Zero(2, 6), state, ws); }, PLEAT_ERROR_INVALID_ARGUMENT,
                   {"motion_encoder", "input x is 2x6", "expected anyx5"});
  MatrixRM small_state = MatrixRM::Zero(2, 8), big_out = MatrixRM::Zero(6, 8);
  expect_error_all([&] { gru_step(gru, MatrixRM::Zero(2, 5), small_state, ws); },
                   PLEAT_ERROR_INVALID_ARGUMENT, {"state is 2x8", "expected 4x8"});
  expect_error_all([&] { gru_window(gru, MatrixRM::Zero(7, 5), 2, out, ws); }, PLEAT_ERROR_INVALID_ARGUMENT,
                   {"7 rows", "2 steps"});
  expect_error_all([&] { gru_window(gru, MatrixRM::Zero(12, 5), 2, big_out, ws); },
                   PLEAT_ERROR_INVALID_ARGUMENT, {"GruWorkspace"});
  Gru bad = gru;
  bad.layers[1].w_hh = MatrixRM::Zero(8, 23);
  expect_error_all([&] { bad.validate(); }, PLEAT_ERROR_INVALID_ARGUMENT,
                   {"layer 1 w_hh is 8x23", "expected 8x24"});
  bad = gru;
  bad.layers[0].b_hh = RowVector::Zero(5);
  expect_error_all([&] { gru_step(bad, MatrixRM::Zero(2, 5), state, ws); }, PLEAT_ERROR_INVALID_ARGUMENT,
                   {"layer 0 b_hh is 1x5"});
}
