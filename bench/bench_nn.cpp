// Per-call times of the nn kernels (medians) and their GFLOP/s against an
// Eigen/OpenBLAS sgemm peak measured in the same run.
// Usage: bench_nn [--quick]   (--quick: fewer repetitions, no 16k graph)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "bench_support.h"
#include "core/topology.h"
#include "nn/gemm.h"
#include "nn/graph_attention.h"
#include "nn/gru.h"
#include "nn/kernel_path.h"
#include "nn/mlp.h"
#include "nn/parallel.h"
#include "spectral/blas_threads.h"

using namespace pleat;
using namespace pleat::nn;

namespace {

using Clock = std::chrono::steady_clock;
int g_reps = 21;

MatrixRM random_matrix(Index r, Index c, std::mt19937& rng, float scale = 1.0f) {
  std::uniform_real_distribution<float> u(-scale, scale);
  MatrixRM m(r, c);
  for (Index i = 0; i < m.size(); ++i) m.data()[i] = u(rng);
  return m;
}

// Triangulated side x side grid: interior vertices have 6 neighbours (7 with
// self), like a regular garment mesh.
Csr grid_graph(int side) {
  Triangles tris((side - 1) * (side - 1) * 2, 3);
  Index t = 0;
  for (int y = 0; y + 1 < side; ++y)
    for (int x = 0; x + 1 < side; ++x) {
      const int a = y * side + x, b = a + 1, c = a + side, d = c + 1;
      tris.row(t++) << a, b, d;
      tris.row(t++) << a, d, c;
    }
  return edge_graph(unique_edges(tris), side * side);
}

GraphAttentionLayer make_layer(AttentionVariant variant, Index in, Index out, int heads, HeadMerge merge,
                               std::mt19937& rng) {
  GraphAttentionLayer l;
  l.variant = variant;
  l.heads = heads;
  l.merge = merge;
  const Index d = merge == HeadMerge::concat ? out / heads : out;
  l.weight = random_matrix(in, heads * d, rng, 1.0f / std::sqrt(float(in)));
  l.attention = random_matrix(heads, 2 * d, rng, 0.3f);
  l.p = RowVector::Constant(heads, 1.2f);
  l.q = RowVector::Constant(heads, 0.8f);
  l.bias = RowVector::Zero(out);
  l.prepare();
  return l;
}

double sgemm_gflops(Index m, Index k, Index n, std::mt19937& rng) {
  const MatrixRM a = random_matrix(m, k, rng), b = random_matrix(k, n, rng);
  MatrixRM c(m, n);
  const double s = pleat_bench::median_seconds([&] { c.noalias() = a * b; }, g_reps);
  const double gf = 2.0 * double(m) * double(k) * double(n) / s * 1e-9;
  std::printf("  sgemm %5ldx%4ldx%4ld  %8.1f us  %6.1f GFLOP/s\n", long(m), long(k), long(n), s * 1e6, gf);
  return gf;
}

// The inference GEMM (nn/gemm.h) on each kernel against OpenBLAS on the same
// operands, single-threaded (as each of the runtime's tasks calls it): the
// per-task shapes of the attention projection, a GRU step and the logits.
void compare_gemm_kernels(std::mt19937& rng) {
  std::printf("inference GEMM, one thread, median us per call (ratio: OpenBLAS time / kernel time)\n");
  std::printf("  %-16s %10s %10s %10s %8s %8s\n", "m x k x n", "OpenBLAS", "baseline", "avx2", "ratio b",
              "ratio a");
  const KernelPath initial = kernel_path();
  pleat::SingleThreadedBlas one_blas_thread;
  for (auto [m, k, n] : {std::tuple<Index, Index, Index>{512, 64, 264},
                         {512, 33, 264},
                         {512, 256, 72},
                         {8, 384, 1152},
                         {512, 64, 31}}) {
    const MatrixRM a = random_matrix(m, k, rng), b = random_matrix(k, n, rng);
    MatrixRM c(m, n);
    const double blas = pleat_bench::median_seconds([&] { c.noalias() = a * b; }, g_reps);
    double t[2] = {NAN, NAN};
    for (KernelPath kernel : {KernelPath::baseline, KernelPath::avx2})
      if (set_kernel_path(kernel))
        t[kernel == KernelPath::avx2] = pleat_bench::median_seconds([&] { gemm(a, b, c); }, g_reps);
    std::printf("  %4ldx%4ldx%5ld %10.1f %10.1f %10.1f %8.2f %8.2f\n", long(m), long(k), long(n), blas * 1e6,
                t[0] * 1e6, t[1] * 1e6, blas / t[0], blas / t[1]);
  }
  set_kernel_path(initial);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  if (quick) g_reps = 7;
  std::mt19937 rng(1);
  {
    std::ifstream load("/proc/loadavg");
    std::string line;
    std::getline(load, line);
    std::printf("load average: %s\n", line.c_str());
  }

  std::printf("Eigen sgemm (EIGEN_USE_BLAS -> OpenBLAS), row-major\n");
  double peak = 0;
  for (auto [m, k, n] :
       {std::tuple<Index, Index, Index>{4096, 128, 128}, {4096, 64, 72}, {16384, 128, 128}, {4096, 256, 256}})
    peak = std::max(peak, sgemm_gflops(m, k, n, rng));
  std::printf("  peak used below: %.1f GFLOP/s\n\n", peak);
  compare_gemm_kernels(rng);

  const int joints = 24;
  // A layer on one thread, and on our 2-thread pool over row blocks
  // (bit-identical results); gemm: its projection alone (nn::gemm, one thread).
  ThreadPool pool(2);
  std::printf(
      "graph attention layer, median us per call (FLOPs: GEMM 2*N*in*(H*d'+2H) + aggregation 2*E*H*d')\n");
  std::printf("  %-32s %6s %7s %9s %9s %9s %8s %6s\n", "layer", "N", "E", "1thread", "pool2", "gemm",
              "GFLOP/s", "%peak");
  std::vector<int> sides = {32, 64, 128};  // ~1k, 4k, 16k vertices
  if (quick) sides.pop_back();
  for (int side : sides) {
    const AttentionGraph graph = attention_graph(grid_graph(side));
    const int n = graph.node_count();
    struct Case {
      const char* label;
      AttentionVariant variant;
      Index in, out;
      HeadMerge merge;
    };
    const Case cases[] = {
        {"flexigat 33->64 (9+S) 4h cat", AttentionVariant::flexigat, 9 + joints, 64, HeadMerge::concat},
        {"flexigat 64->64 4h cat", AttentionVariant::flexigat, 64, 64, HeadMerge::concat},
        {"gat 64->64 4h cat", AttentionVariant::gat, 64, 64, HeadMerge::concat},
        {"lgat 64->64 4h cat", AttentionVariant::lgat, 64, 64, HeadMerge::concat},
        {"flexigat 128->64 4h cat", AttentionVariant::flexigat, 128, 64, HeadMerge::concat},
        {"flexigat 32->3 4h mean (last)", AttentionVariant::flexigat, 32, 3, HeadMerge::mean},
    };
    for (const Case& c : cases) {
      const GraphAttentionLayer layer = make_layer(c.variant, c.in, c.out, 4, c.merge, rng);
      const MatrixRM v = random_matrix(n, c.in, rng);
      MatrixRM out(n, layer.out_width());
      GraphAttentionWorkspace ws;
      ws.reserve(layer, graph);
      MatrixRM z(n, layer.projected_width());
      const double t_gemm = pleat_bench::median_seconds([&] { gemm(v, layer.folded, z); }, g_reps);
      const double t_one =
          pleat_bench::median_seconds([&] { graph_attention_forward(layer, graph, v, out, ws); }, g_reps);
      const double t_pool = pleat_bench::median_seconds(
          [&] { graph_attention_forward(layer, graph, v, out, ws, nullptr, &pool); }, g_reps);
      const double flops = 2.0 * n * double(c.in) * double(layer.projected_width()) +
                           2.0 * double(graph.edge_count()) * double(layer.weight.cols());
      const double best = std::min(t_one, t_pool);
      std::printf("  %-32s %6d %7ld %9.1f %9.1f %9.1f %8.1f %5.1f%%\n", c.label, n, long(graph.edge_count()),
                  t_one * 1e6, t_pool * 1e6, t_gemm * 1e6, flops / best * 1e-9,
                  100.0 * flops / best * 1e-9 / peak);
    }
  }

  // Per-frame graph stacks of DESIGN §4 at ~4k vertices: blend shapes
  // [64, 32, 3] on F (128) and refinement [64, 64, 32, 32, 3] on 6 + S.
  {
    const AttentionGraph graph = attention_graph(grid_graph(64));
    const int n = graph.node_count();
    auto stack = [&](const std::vector<Index>& widths, Index in, Executor* executor) {
      std::vector<GraphAttentionLayer> layers;
      GraphAttentionWorkspace ws;
      Index prev = in;
      for (size_t l = 0; l < widths.size(); ++l) {
        const bool last = l + 1 == widths.size();
        layers.push_back(make_layer(AttentionVariant::flexigat, prev, widths[l], 4,
                                    last ? HeadMerge::mean : HeadMerge::concat, rng));
        layers.back().activation = last ? Activation::identity() : Activation::tanh();
        ws.reserve(layers.back(), graph);
        prev = widths[l];
      }
      const MatrixRM v = random_matrix(n, in, rng);
      std::vector<MatrixRM> acts;
      for (const auto& l : layers) acts.emplace_back(n, l.out_width());
      return pleat_bench::median_seconds(
          [&] {
            for (size_t l = 0; l < layers.size(); ++l)
              graph_attention_forward(layers[l], graph,
                                      l == 0 ? ConstMatrixRef(v) : ConstMatrixRef(acts[l - 1]), acts[l], ws,
                                      nullptr, executor);
          },
          g_reps);
    };
    std::printf("\nper-frame FlexiGAT stacks, N=%d, us:          1thread     pool2\n", n);
    for (int which = 0; which < 2; ++which) {
      const std::vector<Index> widths =
          which == 0 ? std::vector<Index>{64, 32, 3} : std::vector<Index>{64, 64, 32, 32, 3};
      const Index in = which == 0 ? 128 : 6 + joints;
      const double one = stack(widths, in, nullptr), two = stack(widths, in, &pool);
      std::printf("  %-40s %9.1f %9.1f\n",
                  which == 0 ? "blend shapes [64,32,3] on 128" : "refinement [64,64,32,32,3] on 6+S",
                  one * 1e6, two * 1e6);
    }
  }

  // GRU 3 x 128 over a window of 8, one sample and a batch of 64 frames.
  {
    Gru gru;
    const Index in = joints * 6 + 3, h = 128;
    for (int l = 0; l < 3; ++l)
      gru.layers.push_back({random_matrix(l == 0 ? in : h, 3 * h, rng, 0.08f),
                            random_matrix(h, 3 * h, rng, 0.08f), random_matrix(1, 3 * h, rng, 0.08f),
                            random_matrix(1, 3 * h, rng, 0.08f)});
    std::printf("\nGRU 3x128, input %ld, window 8\n", long(in));
    for (Index batch : {Index(1), Index(64)}) {
      GruWorkspace ws;
      ws.reserve(gru, batch);
      const MatrixRM x = random_matrix(8 * batch, in, rng);
      MatrixRM out(batch, h);
      const double s = pleat_bench::median_seconds([&] { gru_window(gru, x, 8, out, ws); }, g_reps * 5);
      double flops = 0;
      for (int l = 0; l < 3; ++l) flops += 2.0 * 8 * double(batch) * double((l == 0 ? in : h) + h) * 3 * h;
      std::printf("  batch %3ld: %8.1f us per call (%.1f us per sample), %.1f GFLOP/s\n", long(batch),
                  s * 1e6, s * 1e6 / double(batch), flops / s * 1e-9);
    }
    GruWorkspace ws;
    ws.reserve(gru, 1);
    const MatrixRM x = random_matrix(1, in, rng);
    MatrixRM state = MatrixRM::Zero(3, h);
    const double s = pleat_bench::median_seconds([&] { gru_step(gru, x, state, ws); }, g_reps * 5);
    std::printf("  streaming step, batch 1: %.1f us\n", s * 1e6);
  }

  // MLP [128, 256, 128] over 13k rows (body encoder: |beta| + S inputs).
  {
    Mlp mlp;
    const Index widths[] = {10 + joints, 128, 256, 128};
    for (int l = 0; l < 3; ++l)
      mlp.layers.push_back({"l" + std::to_string(l), random_matrix(widths[l], widths[l + 1], rng, 0.1f),
                            random_matrix(1, widths[l + 1], rng, 0.1f)});
    mlp.output_activation = Activation::tanh();
    const Index rows = 13000;
    MlpWorkspace ws;
    ws.reserve(mlp, rows);
    const MatrixRM x = random_matrix(rows, widths[0], rng);
    MatrixRM y(rows, 128);
    const double s = pleat_bench::median_seconds([&] { mlp_forward(mlp, x, y, ws); }, g_reps);
    double flops = 0;
    for (int l = 0; l < 3; ++l) flops += 2.0 * rows * double(widths[l]) * double(widths[l + 1]);
    std::printf("\nMLP [128,256,128] over %ld rows (in %ld): %.1f us, %.1f GFLOP/s (%.0f%% of peak)\n",
                long(rows), long(widths[0]), s * 1e6, flops / s * 1e-9, 100.0 * flops / s * 1e-9 / peak);
  }
  return 0;
}
