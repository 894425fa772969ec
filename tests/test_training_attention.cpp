// The trainer's graph-attention layer: its custom autograd op (forward = the
// runtime kernel, backward = the hand-written one) against central finite
// differences in double for every parameter and the input, for GAT, LGAT and
// FlexiGAT with concat and mean heads; its float forward against the
// runtime's layer; and against the generic index_add formulation.
#include <gtest/gtest.h>

#include <random>

#include "attention_op.h"
#include "nn/graph_attention.h"
#include "support/chain_fixtures.h"

using namespace pleat;

namespace {

nn::GraphAttentionLayer random_layer(nn::AttentionVariant variant, nn::HeadMerge merge, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-0.8f, 0.8f);
  nn::GraphAttentionLayer l;
  l.variant = variant;
  l.merge = merge;
  l.activation = merge == nn::HeadMerge::concat ? nn::Activation::tanh() : nn::Activation::identity();
  l.heads = 2;
  const int in = 5, d = 3;
  l.weight.resize(in, 2 * d);
  l.attention.resize(2, 2 * d);
  l.p.resize(2);
  l.q.resize(2);
  l.bias.resize(merge == nn::HeadMerge::concat ? 2 * d : d);
  for (auto* m : {&l.weight, &l.attention})
    for (Eigen::Index i = 0; i < m->size(); ++i) m->data()[i] = u(rng);
  for (auto* v : {&l.p, &l.q, &l.bias})
    for (Eigen::Index i = 0; i < v->size(); ++i) v->data()[i] = u(rng);
  l.p[0] += 1.0f;  // P, Q away from each other
  l.prepare();
  return l;
}

torch::Tensor random_input(int64_t n, int64_t in, torch::Dtype dtype, uint64_t seed) {
  torch::manual_seed(seed);
  return torch::rand({n, in}, torch::TensorOptions().dtype(dtype)) * 2 - 1;
}

struct Variant {
  nn::AttentionVariant variant;
  nn::HeadMerge merge;
};

void check_gradients(Variant c) {
  const nn::AttentionGraph graph = pleat_test::strip_graph(9);
  training::GraphAttention layer(random_layer(c.variant, c.merge, 7));
  layer->to(torch::kFloat64);
  torch::Tensor v = random_input(9, 5, torch::kFloat64, 3).requires_grad_(true);
  torch::manual_seed(4);
  const torch::Tensor r = torch::rand({9, layer->bias.size(0)}, torch::kFloat64) - 0.5;
  const auto loss = [&] { return (layer->forward(v, graph) * r).sum(); };
  loss().backward();

  std::vector<std::pair<std::string, torch::Tensor>> checked = {{"input", v}};
  for (const auto& p : layer->named_parameters())
    if (p.value().requires_grad()) checked.emplace_back(p.key(), p.value());
  EXPECT_EQ(checked.size(), c.variant == nn::AttentionVariant::flexigat ? 6u : 4u);
  torch::NoGradGuard no_grad;
  for (auto& [name, t] : checked) {
    ASSERT_TRUE(t.grad().defined()) << name;
    const torch::Tensor analytic = t.grad().clone();
    auto flat = t.view({-1});
    double largest = 0;
    for (int64_t i = 0; i < flat.numel(); ++i) {
      const double keep = flat[i].item<double>(), h = 1e-6;
      flat[i] = keep + h;
      const double up = loss().item<double>();
      flat[i] = keep - h;
      const double down = loss().item<double>();
      flat[i] = keep;
      const double numeric = (up - down) / (2 * h), got = analytic.view({-1})[i].item<double>();
      largest = std::max(largest, std::abs(numeric));
      ASSERT_NEAR(got, numeric, 1e-6 * (1 + std::abs(numeric))) << name << "[" << i << "]";
    }
    EXPECT_GT(largest, 1e-3) << name << ": the check is not vacuous";
  }
}

}  // namespace

TEST(TrainingAttention, GatGradientsMatchFiniteDifferences) {
  check_gradients({nn::AttentionVariant::gat, nn::HeadMerge::concat});
  check_gradients({nn::AttentionVariant::gat, nn::HeadMerge::mean});
}
TEST(TrainingAttention, LgatGradientsMatchFiniteDifferences) {
  check_gradients({nn::AttentionVariant::lgat, nn::HeadMerge::concat});
  check_gradients({nn::AttentionVariant::lgat, nn::HeadMerge::mean});
}
TEST(TrainingAttention, FlexiGatGradientsMatchFiniteDifferences) {
  check_gradients({nn::AttentionVariant::flexigat, nn::HeadMerge::concat});
  check_gradients({nn::AttentionVariant::flexigat, nn::HeadMerge::mean});
}

// Float forward equals the runtime's layer; the generic index_add version
// gives the same values and gradients; to_layer() round-trips the weights.
TEST(TrainingAttention, MatchesTheRuntimeLayerAndTheGenericOp) {
  const nn::AttentionGraph graph = pleat_test::strip_graph(9);
  for (auto variant : {nn::AttentionVariant::gat, nn::AttentionVariant::lgat, nn::AttentionVariant::flexigat})
    for (auto merge : {nn::HeadMerge::concat, nn::HeadMerge::mean}) {
      const nn::GraphAttentionLayer runtime = random_layer(variant, merge, 11);
      training::GraphAttention layer(runtime);
      const torch::Tensor v = random_input(9, 5, torch::kFloat32, 5);
      nn::MatrixRM input = Eigen::Map<const nn::MatrixRM>(v.data_ptr<float>(), 9, 5);
      nn::MatrixRM expected(9, runtime.out_width());
      nn::GraphAttentionWorkspace ws;
      ws.reserve(runtime, graph);
      nn::graph_attention_forward(runtime, graph, input, expected, ws);
      const torch::Tensor got = layer->forward(v, graph);
      const torch::Tensor want = torch::from_blob(expected.data(), {9, expected.cols()}, torch::kFloat32);
      EXPECT_LT((got - want).abs().max().item<float>(), 2e-6f) << int(variant) << " " << int(merge);

      torch::Tensor a = v.clone().requires_grad_(true), b = v.clone().requires_grad_(true);
      const torch::Tensor r = torch::rand({9, expected.cols()});
      (layer->forward(a, graph) * r).sum().backward();
      const torch::Tensor custom_weight_grad = layer->weight.grad().clone();
      layer->zero_grad();
      const torch::Tensor generic = layer->forward(b, graph, true);
      EXPECT_LT((generic - got).abs().max().item<float>(), 2e-6f);
      (generic * r).sum().backward();
      EXPECT_LT((a.grad() - b.grad()).abs().max().item<float>(), 1e-5f);
      EXPECT_LT((custom_weight_grad - layer->weight.grad()).abs().max().item<float>(), 1e-5f);

      const nn::GraphAttentionLayer back = layer->to_layer();
      EXPECT_EQ(back.weight, runtime.weight);
      EXPECT_EQ(back.attention, runtime.attention);
      EXPECT_EQ(back.bias, runtime.bias);
    }
}
