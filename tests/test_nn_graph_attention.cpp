// Graph attention (GAT / LGAT / FlexiGAT) against hand-computed numbers and a
// naive double-precision reference written from the formulas (unfolded
// attention vectors, explicit neighbour lists), not from the kernel's helpers.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"
#include "nn/gemm.h"
#include "nn/graph_attention.h"
#include "support/expect_error.h"
#include "support/kernel_paths.h"

using namespace pleat;
using namespace pleat::nn;

namespace {

struct Graph {
  Csr csr;
  std::vector<std::vector<int>> neighbourhood;  // attention neighbours incl. self
};

Graph make_graph(int n, const std::vector<std::pair<int, int>>& edges) {
  std::vector<std::set<int>> adj(static_cast<size_t>(n));
  for (auto [a, b] : edges) {
    adj[static_cast<size_t>(a)].insert(b);
    adj[static_cast<size_t>(b)].insert(a);
  }
  Graph g;
  g.csr.offsets.assign(1, 0);
  for (int v = 0; v < n; ++v) {
    for (int j : adj[static_cast<size_t>(v)]) g.csr.indices.push_back(j);
    g.csr.offsets.push_back(static_cast<int32_t>(g.csr.indices.size()));
    std::set<int> with_self = adj[static_cast<size_t>(v)];
    with_self.insert(v);
    g.neighbourhood.emplace_back(with_self.begin(), with_self.end());
  }
  return g;
}

Graph random_graph(int n, double p, std::mt19937& rng) {
  std::bernoulli_distribution coin(p);
  std::vector<std::pair<int, int>> edges;
  for (int a = 0; a < n - 1; ++a)  // the last vertex stays isolated (self loop only)
    for (int b = a + 1; b < n - 1; ++b)
      if (coin(rng)) edges.emplace_back(a, b);
  return make_graph(n, edges);
}

MatrixRM random_matrix(Index r, Index c, std::mt19937& rng, float scale = 1.0f) {
  std::uniform_real_distribution<float> u(-scale, scale);
  MatrixRM m(r, c);
  for (Index i = 0; i < m.size(); ++i) m.data()[i] = u(rng);
  return m;
}

GraphAttentionLayer random_layer(AttentionVariant variant, int heads, HeadMerge merge, Index in,
                                 Index head_width, std::mt19937& rng) {
  GraphAttentionLayer layer;
  layer.name = "test_layer";
  layer.variant = variant;
  layer.heads = heads;
  layer.merge = merge;
  layer.activation = Activation::tanh();
  layer.weight = random_matrix(in, heads * head_width, rng, 0.8f);
  layer.attention = random_matrix(heads, 2 * head_width, rng, 1.5f);
  std::uniform_real_distribution<float> u(-1.0f, 2.0f);
  layer.p.resize(heads);
  layer.q.resize(heads);
  for (int h = 0; h < heads; ++h) {
    layer.p[h] = u(rng);
    layer.q[h] = u(rng);
  }
  layer.bias = random_matrix(1, merge == HeadMerge::concat ? heads * head_width : head_width, rng, 0.3f);
  layer.prepare();
  return layer;
}

struct Reference {
  std::vector<std::vector<double>> out;                 // N x out_width
  std::vector<std::vector<std::vector<double>>> alpha;  // N x |N(i)| x heads
};

// Straight from the formulas (docs/nn.md), in double.
Reference reference(const GraphAttentionLayer& L, const Graph& g, const MatrixRM& v) {
  const int n = static_cast<int>(v.rows()), H = L.heads;
  const int d = static_cast<int>(L.weight.cols()) / H;
  const int in = static_cast<int>(L.weight.rows());
  // z[j][h][c] = sum_k v[j][k] W[k][h*d + c]
  std::vector<std::vector<std::vector<double>>> z(
      n, std::vector<std::vector<double>>(H, std::vector<double>(d, 0.0)));
  for (int j = 0; j < n; ++j)
    for (int h = 0; h < H; ++h)
      for (int c = 0; c < d; ++c) {
        double s = 0;
        for (int k = 0; k < in; ++k) s += double(v(j, k)) * double(L.weight(k, h * d + c));
        z[j][h][c] = s;
      }
  auto norm = [](const std::vector<double>& x) {
    double s = 0;
    for (double e : x) s += e * e;
    return std::sqrt(s);
  };
  Reference ref;
  const bool concat = L.merge == HeadMerge::concat;
  const int width = concat ? H * d : d;
  ref.out.assign(n, std::vector<double>(width, 0.0));
  ref.alpha.resize(n);
  for (int i = 0; i < n; ++i) {
    const auto& nb = g.neighbourhood[i];
    ref.alpha[i].assign(nb.size(), std::vector<double>(H, 0.0));
    for (int h = 0; h < H; ++h) {
      std::vector<double> a_self(d), a_nb(d);
      for (int c = 0; c < d; ++c) {
        a_self[c] = L.attention(h, c);
        a_nb[c] = L.attention(h, d + c);
      }
      double denominator = 1.0;
      if (L.variant == AttentionVariant::lgat) {
        double largest = 0;
        for (int j : nb) largest = std::max(largest, norm(z[j][h]));
        denominator = norm(a_self) * norm(z[i][h]) + norm(a_nb) * largest + double(L.lipschitz_epsilon);
      }
      std::vector<double> e(nb.size());
      double m = -1e300;
      for (size_t k = 0; k < nb.size(); ++k) {
        double raw = 0;
        for (int c = 0; c < d; ++c) raw += a_self[c] * z[i][h][c] + a_nb[c] * z[nb[k]][h][c];
        const double lr = raw > 0 ? raw : 0.2 * raw;
        e[k] = lr / denominator;
        m = std::max(m, e[k]);
      }
      double sum = 0;
      for (double& x : e) sum += (x = std::exp(x - m));
      double P = 1, Q = 1;
      if (L.variant == AttentionVariant::flexigat) {
        P = L.p[h];
        Q = L.q[h];
      }
      for (int c = 0; c < d; ++c) {
        double agg = 0;
        for (size_t k = 0; k < nb.size(); ++k) agg += e[k] / sum * z[nb[k]][h][c];
        const double y = (P - Q) * z[i][h][c] + Q * agg;
        if (concat)
          ref.out[i][h * d + c] += y;
        else
          ref.out[i][c] += y / H;
      }
      for (size_t k = 0; k < nb.size(); ++k) ref.alpha[i][k][h] = e[k] / sum;
    }
    for (int c = 0; c < width; ++c) {
      double y = ref.out[i][c] + (L.bias.size() ? double(L.bias[c]) : 0.0);
      ref.out[i][c] = L.activation.kind == ActivationKind::tanh ? std::tanh(y) : y;
    }
  }
  return ref;
}

MatrixRM run(const GraphAttentionLayer& layer, const AttentionGraph& graph, const MatrixRM& v,
             const GraphAttentionSaved* saved = nullptr) {
  GraphAttentionWorkspace ws;
  ws.reserve(layer, graph);
  MatrixRM out(v.rows(), layer.out_width());
  graph_attention_forward(layer, graph, v, out, ws, saved);
  return out;
}

const char* name_of(AttentionVariant v) {
  return v == AttentionVariant::gat ? "gat" : v == AttentionVariant::lgat ? "lgat" : "flexigat";
}

}  // namespace

TEST(NnAttentionGraph, AddsSelfLoopsSortedAndMerged) {
  Csr csr;
  csr.offsets = {0, 2, 3, 5, 5};
  csr.indices = {2, 1, 0, 0, 2};  // vertex 2 lists itself; vertex 3 isolated
  const AttentionGraph g = attention_graph(csr);
  EXPECT_EQ(g.offsets, (std::vector<int32_t>{0, 3, 5, 7, 8}));
  EXPECT_EQ(g.sources, (std::vector<int32_t>{0, 1, 2, 0, 1, 0, 2, 3}));
  EXPECT_EQ(g.max_degree, 3);
  csr.indices[1] = 7;
  try {
    attention_graph(csr);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), PLEAT_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(e.what()).find("neighbour 7"), std::string::npos) << e.what();
  }
}

// Path 0 - 1 - 2, W = I, a = 0: every logit is 0, so alpha is uniform over
// the neighbourhood and the output is the plain neighbourhood mean.
TEST(NnGraphAttention, HandCheckedUniformAttention) {
  const Graph g = make_graph(3, {{0, 1}, {1, 2}});
  const AttentionGraph graph = attention_graph(g.csr);
  GraphAttentionLayer layer;
  layer.activation = Activation::identity();
  layer.weight = MatrixRM::Identity(2, 2);
  layer.attention = MatrixRM::Zero(1, 4);
  layer.prepare();
  MatrixRM v(3, 2);
  v << 1, 0, 0, 1, 1, 1;
  std::vector<float> alpha(static_cast<size_t>(graph.edge_count()));
  GraphAttentionSaved saved;
  saved.alpha = alpha.data();
  const MatrixRM out = run(layer, graph, v, &saved);
  const float expected[3][2] = {{0.5f, 0.5f}, {2.0f / 3, 2.0f / 3}, {0.5f, 1.0f}};
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 2; ++c) EXPECT_NEAR(out(i, c), expected[i][c], 1e-7f) << i << "," << c;
  EXPECT_FLOAT_EQ(alpha[0], 0.5f);
  EXPECT_FLOAT_EQ(alpha[2], 1.0f / 3);

  // FlexiGAT P = 2, Q = 1 adds the node's own feature once more.
  layer.variant = AttentionVariant::flexigat;
  layer.p = RowVector::Constant(1, 2.0f);
  layer.q = RowVector::Constant(1, 1.0f);
  layer.prepare();
  const MatrixRM flexi = run(layer, graph, v);
  EXPECT_NEAR(flexi(0, 0), 1.5f, 1e-7f);
  EXPECT_NEAR(flexi(0, 1), 0.5f, 1e-7f);
  EXPECT_NEAR(flexi(2, 1), 2.0f, 1e-7f);
}

// Node 0 with neighbours {0, 1}, a_self = 0, a_neighbour = [1, 0], W = I:
// e_00 = LeakyReLU(1) = 1, e_01 = LeakyReLU(-1) = -0.2.
TEST(NnGraphAttention, HandCheckedLeakyReluSoftmax) {
  const Graph g = make_graph(2, {{0, 1}});
  const AttentionGraph graph = attention_graph(g.csr);
  GraphAttentionLayer layer;
  layer.activation = Activation::identity();
  layer.weight = MatrixRM::Identity(2, 2);
  layer.attention = MatrixRM::Zero(1, 4);
  layer.attention(0, 2) = 1.0f;
  layer.prepare();
  MatrixRM v(2, 2);
  v << 1, 0, -1, 1;
  const MatrixRM out = run(layer, graph, v);
  const double w0 = std::exp(1.0), w1 = std::exp(-0.2);
  const double a0 = w0 / (w0 + w1), a1 = w1 / (w0 + w1);
  EXPECT_NEAR(out(0, 0), a0 * 1 + a1 * -1, 1e-6);
  EXPECT_NEAR(out(0, 1), a0 * 0 + a1 * 1, 1e-6);
  EXPECT_NEAR(out(1, 0), a0 * 1 + a1 * -1, 1e-6);  // same neighbourhood, same logits

  // LGAT: ||a_self|| = 0, ||a_neighbour|| = 1, max ||W v_j|| = sqrt(2):
  // logits divided by sqrt(2) + eps.
  layer.variant = AttentionVariant::lgat;
  layer.prepare();
  const MatrixRM lg = run(layer, graph, v);
  const double den = std::sqrt(2.0) + 1e-6;
  const double l0 = std::exp(1.0 / den), l1 = std::exp(-0.2 / den);
  EXPECT_NEAR(lg(0, 0), (l0 - l1) / (l0 + l1), 1e-6);
  EXPECT_NEAR(lg(0, 1), l1 / (l0 + l1), 1e-6);
}

// Both kernel paths (baseline and AVX2, nn/kernel_path.h) on every variant,
// head count, merge mode and the scalar and SIMD widths.
TEST(NnGraphAttention, MatchesNaiveReferenceAllVariants) {
  pleat_test::for_each_kernel_path([](nn::KernelPath) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 3; ++trial) {
      const Graph g = random_graph(14, 0.3, rng);
      const AttentionGraph graph = attention_graph(g.csr);
      for (AttentionVariant variant :
           {AttentionVariant::gat, AttentionVariant::lgat, AttentionVariant::flexigat})
        for (int heads : {1, 2, 3, 4, 8})
          for (HeadMerge merge : {HeadMerge::concat, HeadMerge::mean}) {
            const Index in = 5 + trial, d = trial == 0 ? 3 : trial == 1 ? 4 : 8;  // scalar / SIMD paths
            const GraphAttentionLayer layer = random_layer(variant, heads, merge, in, d, rng);
            const MatrixRM v = random_matrix(14, in, rng);
            std::vector<float> alpha(static_cast<size_t>(graph.edge_count() * heads));
            std::vector<float> pre(static_cast<size_t>(14 * layer.out_width()));
            std::vector<float> z(static_cast<size_t>(14 * layer.projected_width()));
            GraphAttentionSaved saved;
            saved.alpha = alpha.data();
            saved.pre_activation = pre.data();
            saved.projected = z.data();
            const MatrixRM out = run(layer, graph, v, &saved);
            const Reference ref = reference(layer, g, v);
            const std::string what = std::string(name_of(variant)) + " heads " + std::to_string(heads) +
                                     (merge == HeadMerge::concat ? " concat" : " mean") + " trial " +
                                     std::to_string(trial);
            ASSERT_EQ(out.cols(), static_cast<Index>(ref.out[0].size())) << what;
            for (int i = 0; i < 14; ++i) {
              for (Index c = 0; c < out.cols(); ++c) {
                ASSERT_NEAR(out(i, c), ref.out[i][c], 2e-5) << what << " node " << i << " col " << c;
                ASSERT_NEAR(std::tanh(pre[i * out.cols() + c]), out(i, c), 1e-6) << what;
              }
              for (size_t k = 0; k < g.neighbourhood[i].size(); ++k)
                for (int h = 0; h < heads; ++h)
                  ASSERT_NEAR(alpha[(graph.offsets[i] + k) * heads + h], ref.alpha[i][k][h], 2e-6)
                      << what << " alpha node " << i;
            }
            // The saved projection is V [W | S | T].
            const MatrixRM expect_z = v * layer.folded;
            for (Index k = 0; k < expect_z.size(); ++k) ASSERT_NEAR(z[k], expect_z.data()[k], 1e-5);
          }
    }
  });
}

TEST(NnGraphAttention, FlexiGatWithUnitPQEqualsGatExactly) {
  std::mt19937 rng(11);
  const Graph g = random_graph(30, 0.2, rng);
  const AttentionGraph graph = attention_graph(g.csr);
  for (HeadMerge merge : {HeadMerge::concat, HeadMerge::mean}) {
    GraphAttentionLayer gat = random_layer(AttentionVariant::gat, 4, merge, 9, 8, rng);
    GraphAttentionLayer flexi = gat;
    flexi.variant = AttentionVariant::flexigat;
    flexi.p = RowVector::Ones(4);
    flexi.q = RowVector::Ones(4);
    flexi.prepare();
    const MatrixRM v = random_matrix(30, 9, rng);
    const MatrixRM a = run(gat, graph, v), b = run(flexi, graph, v);
    for (Index k = 0; k < a.size(); ++k) ASSERT_EQ(a.data()[k], b.data()[k]) << k;
  }
}

TEST(NnGraphAttention, FlexiGatP1Q0IsolatesNodes) {
  std::mt19937 rng(5);
  const Graph g = random_graph(20, 0.3, rng);
  const AttentionGraph graph = attention_graph(g.csr);
  GraphAttentionLayer layer = random_layer(AttentionVariant::flexigat, 4, HeadMerge::concat, 6, 5, rng);
  layer.p = RowVector::Ones(4);
  layer.q = RowVector::Zero(4);
  layer.prepare();
  MatrixRM v = random_matrix(20, 6, rng);
  const MatrixRM before = run(layer, graph, v);
  // Output is act(W v_i + b).
  const MatrixRM own = ((v * layer.weight).rowwise() + layer.bias).array().tanh().matrix();
  for (Index k = 0; k < own.size(); ++k) ASSERT_NEAR(before.data()[k], own.data()[k], 1e-5);
  // Perturb one vertex: only its own row changes.
  const int victim = g.neighbourhood[0].size() > 1 ? g.neighbourhood[0][1] : 1;
  v.row(victim) *= -3.0f;
  const MatrixRM after = run(layer, graph, v);
  for (Index i = 0; i < 20; ++i) {
    if (i == victim) continue;
    for (Index c = 0; c < after.cols(); ++c) ASSERT_EQ(after(i, c), before(i, c)) << i;
  }
}

TEST(NnGraphAttention, SplitOverThreadsIsBitIdentical) {
  std::mt19937 rng(3);
  const Graph g = random_graph(40, 0.15, rng);
  const AttentionGraph graph = attention_graph(g.csr);
  const GraphAttentionLayer layer = random_layer(AttentionVariant::lgat, 4, HeadMerge::concat, 8, 4, rng);
  const MatrixRM v = random_matrix(40, 8, rng);
  const MatrixRM whole = run(layer, graph, v);
  // Same kernels (the projection through nn::gemm, as the layer runs it: an
  // Eigen product compiled here rounds differently from the AVX2 + FMA
  // build), nodes split over two threads.
  MatrixRM z(v.rows(), layer.folded.cols());
  gemm(v, layer.folded, z);
  const AttentionParams params = attention_params(layer);
  std::vector<float> norms(40 * 4), out(40 * 16);
  std::vector<float> s1(attention_scratch_floats(4, 16, graph)), s2(s1.size());
  attention_node_norms(params, z.data(), z.cols(), 0, 40, norms.data());
  std::thread t1([&] {
    attention_aggregate(params, graph, z.data(), z.cols(), norms.data(), 0, 17, out.data(), 16, nullptr,
                        s1.data(), nullptr);
  });
  std::thread t2([&] {
    attention_aggregate(params, graph, z.data(), z.cols(), norms.data(), 17, 40, out.data(), 16, nullptr,
                        s2.data(), nullptr);
  });
  t1.join();
  t2.join();
  apply_activation(layer.activation, out.data(), static_cast<Index>(out.size()));
  for (size_t k = 0; k < out.size(); ++k) ASSERT_EQ(out[k], whole.data()[k]) << k;
}

TEST(NnGraphAttention, WorkspaceIsReusedAcrossLayersAndCalls) {
  std::mt19937 rng(9);
  const Graph g = random_graph(25, 0.2, rng);
  const AttentionGraph graph = attention_graph(g.csr);
  const GraphAttentionLayer l1 = random_layer(AttentionVariant::flexigat, 4, HeadMerge::concat, 7, 4, rng);
  const GraphAttentionLayer l2 = random_layer(AttentionVariant::lgat, 4, HeadMerge::mean, 16, 3, rng);
  GraphAttentionWorkspace ws;
  ws.reserve(l1, graph);
  ws.reserve(l2, graph);
  const size_t capacity = ws.scratch().capacity();
  const float* data = ws.scratch().data();
  const MatrixRM v = random_matrix(25, 7, rng);
  MatrixRM h(25, 16), y(25, 3), y_first;
  for (int call = 0; call < 3; ++call) {
    graph_attention_forward(l1, graph, v, h, ws);
    graph_attention_forward(l2, graph, h, y, ws);
    if (call == 0) y_first = y;
    for (Index k = 0; k < y.size(); ++k) ASSERT_EQ(y.data()[k], y_first.data()[k]);
  }
  EXPECT_EQ(ws.scratch().capacity(), capacity);
  EXPECT_EQ(ws.scratch().data(), data);
}

namespace {
using pleat_test::expect_error_all;
}  // namespace

TEST(NnGraphAttention, ShapeErrorsNameTheTensor) {
  std::mt19937 rng(1);
  const Graph g = random_graph(6, 0.5, rng);
  const AttentionGraph graph = attention_graph(g.csr);
  GraphAttentionLayer layer = random_layer(AttentionVariant::flexigat, 2, HeadMerge::concat, 4, 3, rng);
  GraphAttentionWorkspace ws;
  ws.reserve(layer, graph);
  MatrixRM out(6, 6);
  expect_error_all([&] { graph_attention_forward(layer, graph, MatrixRM::Zero(6, 5), out, ws); },
                   PLEAT_ERROR_INVALID_ARGUMENT, {"test_layer", "input V is 6x5", "expected 6x4"});
  expect_error_all([&] { graph_attention_forward(layer, graph, MatrixRM::Zero(5, 4), out, ws); },
                   PLEAT_ERROR_INVALID_ARGUMENT, {"input V is 5x4", "expected 6x4"});
  MatrixRM bad_out(6, 3);
  expect_error_all([&] { graph_attention_forward(layer, graph, MatrixRM::Zero(6, 4), bad_out, ws); },
                   PLEAT_ERROR_INVALID_ARGUMENT, {"output is 6x3", "expected 6x6"});
  GraphAttentionWorkspace empty;
  expect_error_all([&] { graph_attention_forward(layer, graph, MatrixRM::Zero(6, 4), out, empty); },
                   PLEAT_ERROR_INVALID_ARGUMENT, {"GraphAttentionWorkspace", "reserve()"});
  GraphAttentionLayer bad = layer;
  bad.attention = MatrixRM::Zero(2, 5);
  expect_error_all([&] { bad.prepare(); }, PLEAT_ERROR_INVALID_ARGUMENT,
                   {"test_layer", "attention is 2x5", "expected 2x6"});
  bad = layer;
  bad.q = RowVector::Zero(3);
  expect_error_all([&] { bad.prepare(); }, PLEAT_ERROR_INVALID_ARGUMENT,
                   {"q (flexigat) is 1x3", "expected 1x2"});
  bad = layer;
  bad.weight = MatrixRM::Zero(4, 7);
  expect_error_all([&] { bad.prepare(); }, PLEAT_ERROR_INVALID_ARGUMENT, {"7 columns", "2 heads"});
  bad = layer;
  bad.weight = MatrixRM::Zero(5, 6);  // changed without prepare()
  expect_error_all([&] { graph_attention_forward(bad, graph, MatrixRM::Zero(6, 5), out, ws); },
                   PLEAT_ERROR_INVALID_ARGUMENT, {"prepare()"});
}

TEST(NnThreadPool, RunsEveryTaskOnceAcrossManyRuns) {
  ThreadPool pool(3);
  EXPECT_EQ(pool.concurrency(), 3);
  std::vector<std::atomic<int>> hits(97);
  struct Ctx {
    std::vector<std::atomic<int>>* hits;
  } ctx{&hits};
  for (int run = 0; run < 200; ++run) {
    const int32_t tasks = 1 + run % 97;
    pool.run(
        tasks, [](void* c, int32_t t) { (*static_cast<Ctx*>(c)->hits)[static_cast<size_t>(t)]++; }, &ctx);
  }
  int total = 0;
  for (auto& h : hits) total += h.load();
  int expected = 0;
  for (int run = 0; run < 200; ++run) expected += 1 + run % 97;
  EXPECT_EQ(total, expected);
}

// Several task blocks (N > kAttentionTaskRows): any executor gives the same bits.
TEST(NnGraphAttention, ThreadPoolIsBitIdenticalToSerial) {
  std::mt19937 rng(21);
  // A ring with chords: 1300 nodes, degree 5 + self.
  std::vector<std::pair<int, int>> edges;
  const int n = 1300;
  for (int i = 0; i < n; ++i) {
    edges.emplace_back(i, (i + 1) % n);
    edges.emplace_back(i, (i + 37) % n);
  }
  const Graph g = make_graph(n, edges);
  const AttentionGraph graph = attention_graph(g.csr);
  ThreadPool pool2(2), pool3(3);
  for (AttentionVariant variant : {AttentionVariant::flexigat, AttentionVariant::lgat}) {
    const GraphAttentionLayer layer = random_layer(variant, 4, HeadMerge::concat, 12, 8, rng);
    const MatrixRM v = random_matrix(n, 12, rng);
    GraphAttentionWorkspace ws;
    ws.reserve(layer, graph);
    MatrixRM serial(n, 32), two(n, 32), three(n, 32);
    std::vector<float> alpha1(static_cast<size_t>(graph.edge_count() * 4)), alpha2(alpha1.size());
    GraphAttentionSaved s1, s2;
    s1.alpha = alpha1.data();
    s2.alpha = alpha2.data();
    graph_attention_forward(layer, graph, v, serial, ws, &s1);
    graph_attention_forward(layer, graph, v, two, ws, &s2, &pool2);
    graph_attention_forward(layer, graph, v, three, ws, nullptr, &pool3);
    for (Index k = 0; k < serial.size(); ++k) {
      ASSERT_EQ(serial.data()[k], two.data()[k]) << k;
      ASSERT_EQ(serial.data()[k], three.data()[k]) << k;
    }
    for (size_t k = 0; k < alpha1.size(); ++k) ASSERT_EQ(alpha1[k], alpha2[k]);
    // And it matches the naive reference.
    const Reference ref = reference(layer, g, v);
    for (int i = 0; i < n; i += 13)
      for (int c = 0; c < 32; ++c) ASSERT_NEAR(serial(i, c), ref.out[i][c], 2e-5);
  }
}
