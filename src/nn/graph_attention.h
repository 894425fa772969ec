#pragma once
// One graph-attention kernel for GAT, LGAT and FlexiGAT (DESIGN §4, paper
// Eq. 3-6). Exact formulas: docs/nn.md. In short, per head h of width d':
//
//   z_j^h   = v_j W_h                          (row vector, d')
//   r_ij^h  = v_i s_h + v_j t_h  (= a_h . [z_i^h | z_j^h]) with s_h = W_h a_h[:d'],
//                                                          t_h = W_h a_h[d':]
//   e_ij^h  = LeakyReLU_0.2(r_ij^h)                          (gat, flexigat)
//   e_ij^h  = LeakyReLU_0.2(r_ij^h * (1 / c_i^h))            (lgat), where
//   c_i^h   = ||a_h[:d']|| ||z_i^h|| + max_{k in N(i)} ||a_h[d':]|| ||z_k^h|| + eps
//             (= LeakyReLU(r) / c exactly in real arithmetic: c > 0 and
//              LeakyReLU is positively homogeneous)
//   alpha_ij^h = softmax over j in N(i) (N(i) includes i itself)
//   y_i^h   = (P_h - Q_h) z_i^h + Q_h sum_j alpha_ij^h z_j^h    (gat, lgat: P = Q = 1)
//   y_i     = [y_i^1 | ... | y_i^H] (concat)  or  (1/H) sum_h y_i^h (mean)
//   out_i   = act(y_i + bias)
//
// The forward splits into a GEMM (project: Z = V [W | S | T], the attention
// vectors folded in as 2H extra columns) and a raw-buffer kernel over Z
// (attention_aggregate: fused logits -> max -> exp -> sum -> weighted sum
// per destination node), which is what a trainer wraps as an autograd op with
// its backward next to it (the GEMM's backward is the framework's).
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "core/mesh.h"
#include "nn/activation.h"
#include "nn/kernel_params.h"
#include "nn/parallel.h"
#include "nn/tensor.h"

namespace pleat::nn {

// CSR by destination: the sources (attention neighbourhood) of node i are
// sources[offsets[i] .. offsets[i+1]), sorted ascending, including i itself.
// Edge e's attention coefficients are stored at alpha[e * heads + h].
struct AttentionGraph {
  std::vector<int32_t> offsets{0};
  std::vector<int32_t> sources;
  int32_t max_degree = 0;  // largest neighbourhood (self included)

  int32_t node_count() const { return static_cast<int32_t>(offsets.size()) - 1; }
  int64_t edge_count() const { return static_cast<int64_t>(sources.size()); }
};

// Neighbours of the mesh graph plus a self loop per vertex (duplicates and any
// self loop already present are merged). Throws on an index out of range or
// offsets that are not monotone.
AttentionGraph attention_graph(const Csr& graph);

enum class AttentionVariant : int32_t { gat = 0, lgat = 1, flexigat = 2 };
struct GraphAttentionLayer {
  std::string name = "graph_attention";
  AttentionVariant variant = AttentionVariant::gat;
  HeadMerge merge = HeadMerge::concat;
  Activation activation = Activation::tanh();
  int32_t heads = 1;
  MatrixRM weight;     // in x (heads * d'); head h owns columns [h*d', (h+1)*d')
  MatrixRM attention;  // heads x 2d'; row h = a_h = [a_self (applied to z_i) | a_neighbour (z_j)]
  RowVector p, q;      // heads; used by flexigat only (gat and lgat use P = Q = 1)
  RowVector bias;      // out_width, or empty for no bias
  float negative_slope = 0.2f;
  float lipschitz_epsilon = 1e-6f;  // lgat

  Index in_width() const { return weight.rows(); }
  Index head_width() const { return heads > 0 ? weight.cols() / heads : 0; }
  Index out_width() const { return merge == HeadMerge::concat ? weight.cols() : head_width(); }
  // Columns of the projection Z = V [W | S | T]: heads*d' + 2*heads.
  Index projected_width() const { return weight.cols() + 2 * heads; }

  // Validates the shapes and builds the derived tensors below. Call after
  // loading or changing any parameter; the forward throws if they are stale
  // in shape (it cannot see changed values).
  void prepare();
  MatrixRM folded;                  // in x projected_width: [W | S | T]
  RowVector self_norm;              // heads: ||a_h[:d']||
  RowVector neighbour_norm;         // heads: ||a_h[d':]||
  RowVector self_coefficient;       // heads: P - Q (0 for gat, lgat)
  RowVector neighbour_coefficient;  // heads: Q (1 for gat, lgat)
};

// The raw-buffer kernel (everything after the GEMM) takes AttentionParamsT
// (nn/kernel_params.h). It exists for float (the runtime, training) and
// double (gradient checks of the trainer's backward).
// Pointer arguments take their scalar type from the params (so nullptr binds).
template <typename T>
using NonDeduced = typename std::enable_if<true, T>::type;

using AttentionParams = AttentionParamsT<float>;
AttentionParams attention_params(const GraphAttentionLayer& layer);

// Per-node head norms ||z_j^h|| for LGAT: norms[j * heads + h], nodes
// [begin, end). projected: N x (heads*d' + 2*heads), row stride zstride.
template <typename Scalar>
void attention_node_norms(const AttentionParamsT<Scalar>& params, const Scalar* projected, Index zstride,
                          int32_t begin, int32_t end, Scalar* norms);

// The fused kernel for destination nodes [begin, end): writes
// y_i + bias (pre-activation) to out (row stride ostride). Nodes are
// independent, so any split of [0, N) over threads gives bit-identical
// results for one kernel path (nn/kernel_path.h; the AVX2 and baseline paths
// differ by rounding, FMA). norms: from attention_node_norms over ALL nodes (lipschitz only,
// else null). alpha: E x heads output (saved softmax, for a backward) or null.
// scratch: attention_scratch_floats(heads, heads * head_width, graph) floats,
// private to the calling thread.
// lipschitz_denominator: N x heads output (the divisor of each logit) or null.
template <typename Scalar>
void attention_aggregate(const AttentionParamsT<Scalar>& params, const AttentionGraph& graph,
                         const NonDeduced<Scalar>* projected, Index zstride, const NonDeduced<Scalar>* norms,
                         int32_t begin, int32_t end, NonDeduced<Scalar>* out, Index ostride,
                         NonDeduced<Scalar>* alpha, NonDeduced<Scalar>* scratch,
                         NonDeduced<Scalar>* lipschitz_denominator);

size_t attention_scratch_floats(size_t heads, size_t heads_times_width, const AttentionGraph& graph);

// Intermediate values a backward needs, each optional (null: not saved).
// Row-major, contiguous.
struct GraphAttentionSaved {
  float* projected = nullptr;              // N x projected_width: Z = V [W | S | T]
  float* alpha = nullptr;                  // E x heads, edge order of the AttentionGraph
  float* lipschitz_denominator = nullptr;  // N x heads (lgat)
  float* pre_activation = nullptr;         // N x out_width: y + bias
};

class GraphAttentionWorkspace {
 public:
  // Sizes for this layer on this graph; call once per layer of a stack (it
  // only grows) before the hot path.
  void reserve(const GraphAttentionLayer& layer, const AttentionGraph& graph);
  static size_t floats_needed(const GraphAttentionLayer& layer, const AttentionGraph& graph);
  Scratch& scratch() { return scratch_; }

 private:
  Scratch scratch_;
};

// Rows per task of the forward: the GEMM and the aggregation run in blocks of
// this many nodes whatever the executor, so outputs are bit-identical for any
// thread count.
constexpr int32_t kAttentionTaskRows = 512;

// v: N x in_width, out: N x out_width (must not alias v). Two fork-join
// phases on `executor` (null: the calling thread): Z = V [W | S | T] (+ LGAT
// norms) per block of rows, then the fused aggregation + bias + activation
// per block. Allocates nothing (throws if the workspace is too small).
void graph_attention_forward(const GraphAttentionLayer& layer, const AttentionGraph& graph, ConstMatrixRef v,
                             MatrixRef out, GraphAttentionWorkspace& workspace,
                             const GraphAttentionSaved* saved = nullptr, Executor* executor = nullptr);

}  // namespace pleat::nn
