// The backward of the graph-attention kernel (nn/graph_attention_backward.h)
// against central finite differences of the forward kernel, in double, for
// GAT, LGAT and FlexiGAT, concat and mean heads: every entry of Z, the
// per-head coefficients P - Q and Q, and LGAT's attention-vector norms.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "nn/graph_attention.h"
#include "nn/graph_attention_backward.h"
#include "support/chain_fixtures.h"

using namespace pleat;
using namespace pleat::nn;

namespace {

struct Case {
  bool lipschitz;
  bool flexible;
  HeadMerge merge;
};

struct Problem {
  int n = 9, heads = 2, d = 3;
  AttentionGraph graph = pleat_test::strip_graph(9);
  std::vector<double> z, self_coefficient, neighbour_coefficient, self_norm, neighbour_norm, r;
  Case c;
  Index zstride() const { return heads * d + 2 * heads; }
  Index out_width() const { return c.merge == HeadMerge::concat ? heads * d : d; }

  AttentionParamsT<double> params() const {
    AttentionParamsT<double> p;
    p.heads = heads;
    p.head_width = d;
    p.merge = c.merge;
    p.lipschitz = c.lipschitz;
    p.negative_slope = 0.2;
    p.lipschitz_epsilon = 1e-6;
    p.self_coefficient = self_coefficient.data();
    p.neighbour_coefficient = neighbour_coefficient.data();
    p.self_norm = self_norm.data();
    p.neighbour_norm = neighbour_norm.data();
    return p;
  }

  // L = sum(y ⊙ r), with the forward's saved alpha, norms and divisors.
  double loss(std::vector<double>* alpha = nullptr, std::vector<double>* norms = nullptr,
              std::vector<double>* divisors = nullptr) const {
    const AttentionParamsT<double> p = params();
    std::vector<double> nrm(static_cast<size_t>(n) * heads), div(static_cast<size_t>(n) * heads);
    std::vector<double> a(static_cast<size_t>(graph.edge_count()) * heads);
    std::vector<double> y(static_cast<size_t>(n) * out_width());
    std::vector<double> scratch(attention_scratch_floats(heads, heads * d, graph));
    if (c.lipschitz) attention_node_norms(p, z.data(), zstride(), 0, n, nrm.data());
    attention_aggregate(p, graph, z.data(), zstride(), c.lipschitz ? nrm.data() : nullptr, 0, n, y.data(),
                        out_width(), a.data(), scratch.data(), c.lipschitz ? div.data() : nullptr);
    if (alpha) *alpha = a;
    if (norms) *norms = nrm;
    if (divisors) *divisors = div;
    double l = 0;
    for (size_t i = 0; i < y.size(); ++i) l += y[i] * r[i];
    return l;
  }
};

Problem make(Case c, uint32_t seed) {
  Problem p;
  p.c = c;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  p.z.resize(static_cast<size_t>(p.n) * p.zstride());
  for (double& x : p.z) x = u(rng);
  p.self_coefficient = {c.flexible ? 0.7 : 0.0, c.flexible ? -0.4 : 0.0};
  p.neighbour_coefficient = {c.flexible ? 0.6 : 1.0, c.flexible ? 1.3 : 1.0};
  p.self_norm = {0.8, 1.5};
  p.neighbour_norm = {1.1, 0.6};
  p.r.resize(static_cast<size_t>(p.n) * p.out_width());
  for (double& x : p.r) x = u(rng);
  return p;
}

// Central difference of L with respect to *x.
double numeric(Problem& p, double* x) {
  const double h = 1e-6, keep = *x;
  *x = keep + h;
  const double up = p.loss();
  *x = keep - h;
  const double down = p.loss();
  *x = keep;
  return (up - down) / (2 * h);
}

void check(Case c) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    Problem p = make(c, seed);
    std::vector<double> alpha, norms, divisors;
    p.loss(&alpha, &norms, &divisors);
    std::vector<double> grad_z(p.z.size()), gs(2), gq(2), gsn(2), gnn(2);
    attention_aggregate_backward(p.params(), p.graph, p.z.data(), p.zstride(), alpha.data(),
                                 c.lipschitz ? norms.data() : nullptr,
                                 c.lipschitz ? divisors.data() : nullptr, p.r.data(), p.out_width(),
                                 grad_z.data(), gs.data(), gq.data(), gsn.data(), gnn.data());
    double largest = 0;
    for (size_t i = 0; i < p.z.size(); ++i) {
      const double want = numeric(p, &p.z[i]);
      largest = std::max(largest, std::abs(want));
      ASSERT_NEAR(grad_z[i], want, 1e-6 * (1 + std::abs(want)))
          << "dL/dZ[" << i / p.zstride() << ", " << i % p.zstride() << "] seed " << seed;
    }
    EXPECT_GT(largest, 0.1) << "the check is not vacuous";
    for (int h = 0; h < 2; ++h) {
      EXPECT_NEAR(gs[h], numeric(p, &p.self_coefficient[h]), 1e-6) << "dL/d(P-Q) head " << h;
      EXPECT_NEAR(gq[h], numeric(p, &p.neighbour_coefficient[h]), 1e-6) << "dL/dQ head " << h;
      if (c.lipschitz) {
        EXPECT_NEAR(gsn[h], numeric(p, &p.self_norm[h]), 1e-6) << "dL/d||a_self|| head " << h;
        EXPECT_NEAR(gnn[h], numeric(p, &p.neighbour_norm[h]), 1e-6) << "dL/d||a_neighbour|| head " << h;
      }
    }
  }
}

}  // namespace

TEST(NnAttentionBackward, GatConcatMatchesFiniteDifferences) {
  check({false, false, HeadMerge::concat});
}
TEST(NnAttentionBackward, GatMeanMatchesFiniteDifferences) {
  check({false, false, HeadMerge::mean});
}
TEST(NnAttentionBackward, LgatConcatMatchesFiniteDifferences) {
  check({true, false, HeadMerge::concat});
}
TEST(NnAttentionBackward, LgatMeanMatchesFiniteDifferences) {
  check({true, false, HeadMerge::mean});
}
TEST(NnAttentionBackward, FlexiGatConcatMatchesFiniteDifferences) {
  check({false, true, HeadMerge::concat});
}
TEST(NnAttentionBackward, FlexiGatMeanMatchesFiniteDifferences) {
  check({false, true, HeadMerge::mean});
}
