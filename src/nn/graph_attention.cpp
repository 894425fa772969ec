#include "nn/graph_attention.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "nn/gemm.h"
#include "nn/kernel_path.h"
#include "nn/kernels/entry_points.h"

namespace pleat::nn {

namespace {

constexpr const char* kAttentionKind = "graph attention layer";

const char* variant_name(AttentionVariant v) {
  switch (v) {
    case AttentionVariant::gat: return "gat";
    case AttentionVariant::lgat: return "lgat";
    case AttentionVariant::flexigat: return "flexigat";
  }
  return "?";
}

}  // namespace

AttentionGraph attention_graph(const Csr& graph) {
  const int32_t n = graph.vertex_count();
  if (n < 0 || graph.offsets.empty() || graph.offsets.front() != 0 ||
      static_cast<size_t>(graph.offsets.back()) != graph.indices.size())
    invalid(
        kAttentionKind, "attention_graph",
        "mesh graph offsets are inconsistent with its " + std::to_string(graph.indices.size()) + " indices");
  AttentionGraph out;
  out.offsets.assign(static_cast<size_t>(n) + 1, 0);
  out.sources.reserve(graph.indices.size() + static_cast<size_t>(n));
  std::vector<int32_t> row;
  for (int32_t v = 0; v < n; ++v) {
    const int32_t b = graph.offsets[v], e = graph.offsets[v + 1];
    if (e < b)
      invalid(kAttentionKind, "attention_graph",
              "mesh graph offsets decrease at vertex " + std::to_string(v));
    row.assign(graph.indices.begin() + b, graph.indices.begin() + e);
    for (int32_t j : row)
      if (j < 0 || j >= n)
        invalid(kAttentionKind, "attention_graph",
                "mesh graph vertex " + std::to_string(v) + " has neighbour " + std::to_string(j) +
                    ", expected 0.." + std::to_string(n - 1));
    row.push_back(v);
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    out.sources.insert(out.sources.end(), row.begin(), row.end());
    out.offsets[static_cast<size_t>(v) + 1] = static_cast<int32_t>(out.sources.size());
    out.max_degree = std::max(out.max_degree, static_cast<int32_t>(row.size()));
  }
  return out;
}

void GraphAttentionLayer::prepare() {
  if (heads < 1 || heads > kMaxAttentionHeads)
    invalid(kAttentionKind, name,
            "heads is " + std::to_string(heads) + ", expected 1.." + std::to_string(kMaxAttentionHeads));
  if (weight.size() == 0) invalid(kAttentionKind, name, "weight is empty");
  if (weight.cols() % heads != 0)
    invalid(kAttentionKind, name,
            "weight has " + std::to_string(weight.cols()) + " columns, not a multiple of the " +
                std::to_string(heads) + " heads");
  const Index d = head_width();
  check_shape(kAttentionKind, name, "attention", attention.rows(), attention.cols(), heads, 2 * d);
  if (variant == AttentionVariant::flexigat) {
    check_shape(kAttentionKind, name, "p (flexigat)", 1, p.size(), 1, heads);
    check_shape(kAttentionKind, name, "q (flexigat)", 1, q.size(), 1, heads);
  }
  if (bias.size() != 0) check_shape(kAttentionKind, name, "bias", 1, bias.size(), 1, out_width());
  if (!weight.allFinite() || !attention.allFinite() || !bias.allFinite() ||
      (variant == AttentionVariant::flexigat && (!p.allFinite() || !q.allFinite())))
    invalid(
        kAttentionKind, name,
        std::string("a parameter of the ") + variant_name(variant) + " layer holds a NaN or infinite value");
  if (!(lipschitz_epsilon > 0.0f) && variant == AttentionVariant::lgat)
    invalid(kAttentionKind, name, "lipschitz_epsilon must be > 0");

  const Index width = weight.cols();
  folded.resize(weight.rows(), projected_width());
  folded.leftCols(width) = weight;
  self_norm.resize(heads);
  neighbour_norm.resize(heads);
  self_coefficient.resize(heads);
  neighbour_coefficient.resize(heads);
  for (int32_t h = 0; h < heads; ++h) {
    const auto w = weight.middleCols(h * d, d);
    const auto a_self = attention.row(h).head(d);
    const auto a_neighbour = attention.row(h).tail(d);
    folded.col(width + h) = w * a_self.transpose();
    folded.col(width + heads + h) = w * a_neighbour.transpose();
    self_norm[h] = a_self.norm();
    neighbour_norm[h] = a_neighbour.norm();
    const bool flexible = variant == AttentionVariant::flexigat;
    self_coefficient[h] = flexible ? p[h] - q[h] : 0.0f;
    neighbour_coefficient[h] = flexible ? q[h] : 1.0f;
  }
}

AttentionParams attention_params(const GraphAttentionLayer& layer) {
  AttentionParams params;
  params.heads = layer.heads;
  params.head_width = static_cast<int32_t>(layer.head_width());
  params.merge = layer.merge;
  params.lipschitz = layer.variant == AttentionVariant::lgat;
  params.negative_slope = layer.negative_slope;
  params.lipschitz_epsilon = layer.lipschitz_epsilon;
  params.self_coefficient = layer.self_coefficient.data();
  params.neighbour_coefficient = layer.neighbour_coefficient.data();
  params.self_norm = layer.self_norm.data();
  params.neighbour_norm = layer.neighbour_norm.data();
  params.bias = layer.bias.size() != 0 ? layer.bias.data() : nullptr;
  return params;
}

template <typename Scalar>
void attention_node_norms(const AttentionParamsT<Scalar>& params, const Scalar* projected, Index zstride,
                          int32_t begin, int32_t end, Scalar* norms) {
  const int32_t heads = params.heads;
  const Index d = params.head_width;
  for (int32_t j = begin; j < end; ++j) {
    const Scalar* zj = projected + static_cast<Index>(j) * zstride;
    for (int32_t h = 0; h < heads; ++h) {
      Scalar s = 0;
      for (Index k = 0; k < d; ++k) s += zj[h * d + k] * zj[h * d + k];
      norms[static_cast<Index>(j) * heads + h] = std::sqrt(s);
    }
  }
}

template <typename Scalar>
void attention_aggregate(const AttentionParamsT<Scalar>& params, const AttentionGraph& graph,
                         const NonDeduced<Scalar>* projected, Index zstride, const NonDeduced<Scalar>* norms,
                         int32_t begin, int32_t end, NonDeduced<Scalar>* out, Index ostride,
                         NonDeduced<Scalar>* alpha, NonDeduced<Scalar>* scratch,
                         NonDeduced<Scalar>* lipschitz_denominator) {
  const kernels::AggregateCall<Scalar> call{&params,
                                            graph.offsets.data(),
                                            graph.sources.data(),
                                            projected,
                                            zstride,
                                            norms,
                                            begin,
                                            end,
                                            out,
                                            ostride,
                                            alpha,
                                            scratch,
                                            lipschitz_denominator};
  if (kernel_path() == KernelPath::avx2)
    kernels::attention_aggregate_avx2(call);
  else
    kernels::attention_aggregate_baseline(call);
}

template void attention_node_norms(const AttentionParamsT<float>&, const float*, Index, int32_t, int32_t,
                                   float*);
template void attention_node_norms(const AttentionParamsT<double>&, const double*, Index, int32_t, int32_t,
                                   double*);
template void attention_aggregate(const AttentionParamsT<float>&, const AttentionGraph&, const float*, Index,
                                  const float*, int32_t, int32_t, float*, Index, float*, float*, float*);
template void attention_aggregate(const AttentionParamsT<double>&, const AttentionGraph&, const double*,
                                  Index, const double*, int32_t, int32_t, double*, Index, double*, double*,
                                  double*);

size_t attention_scratch_floats(size_t heads, size_t heads_times_width, const AttentionGraph& graph) {
  return heads_times_width + static_cast<size_t>(std::max(graph.max_degree, 0)) * heads;
}

namespace {

// Everything one forward's tasks share (rows [t * kAttentionTaskRows, ...)).
struct ForwardJob {
  const AttentionParams* params;
  const AttentionGraph* graph;
  const MatrixRM* folded;
  const float* v;
  Index v_stride;
  Index in_width;
  float* z;
  Index z_width;
  float* norms;   // lgat only
  float* target;  // pre-activation rows (the output itself unless saved)
  Index target_stride;
  float* out;
  Index out_stride;
  Index out_width;
  float* alpha;
  float* lipschitz_denominator;
  float* scratch;
  size_t scratch_per_task;
  Activation activation;
  int32_t n;
};

void project_task(void* context, int32_t task) {
  const ForwardJob& job = *static_cast<const ForwardJob*>(context);
  const int32_t begin = task * kAttentionTaskRows;
  const int32_t end = std::min(job.n, begin + kAttentionTaskRows);
  MatrixMap z = view(job.z + static_cast<Index>(begin) * job.z_width, end - begin, job.z_width);
  gemm(view(job.v + static_cast<Index>(begin) * job.v_stride, end - begin, job.in_width, job.v_stride),
       *job.folded, z);
  if (job.norms != nullptr) attention_node_norms(*job.params, job.z, job.z_width, begin, end, job.norms);
}

void aggregate_task(void* context, int32_t task) {
  const ForwardJob& job = *static_cast<const ForwardJob*>(context);
  const int32_t begin = task * kAttentionTaskRows;
  const int32_t end = std::min(job.n, begin + kAttentionTaskRows);
  attention_aggregate(
      *job.params, *job.graph, job.z, job.z_width, job.norms, begin, end, job.target, job.target_stride,
      job.alpha, job.scratch + static_cast<size_t>(task) * job.scratch_per_task, job.lipschitz_denominator);
  MatrixMap out =
      view(job.out + static_cast<Index>(begin) * job.out_stride, end - begin, job.out_width, job.out_stride);
  if (job.target != job.out)
    out = view(static_cast<const float*>(job.target) + static_cast<Index>(begin) * job.target_stride,
               end - begin, job.out_width, job.target_stride);
  apply_activation(job.activation, out);
}

int32_t task_count(int32_t n) {
  return (n + kAttentionTaskRows - 1) / kAttentionTaskRows;
}

}  // namespace

size_t GraphAttentionWorkspace::floats_needed(const GraphAttentionLayer& layer, const AttentionGraph& graph) {
  const int32_t n = std::max(graph.node_count(), 0);
  const size_t nn = static_cast<size_t>(n);
  const size_t heads = static_cast<size_t>(std::max(layer.heads, 1));
  return nn * static_cast<size_t>(layer.projected_width()) + nn * heads +
         static_cast<size_t>(task_count(n)) *
             attention_scratch_floats(heads, static_cast<size_t>(layer.weight.cols()), graph);
}

void GraphAttentionWorkspace::reserve(const GraphAttentionLayer& layer, const AttentionGraph& graph) {
  scratch_.reserve(floats_needed(layer, graph));
}

void graph_attention_forward(const GraphAttentionLayer& layer, const AttentionGraph& graph, ConstMatrixRef v,
                             MatrixRef out, GraphAttentionWorkspace& workspace,
                             const GraphAttentionSaved* saved, Executor* executor) {
  const std::string& name = layer.name;
  const int32_t heads = layer.heads;
  if (heads < 1 || heads > kMaxAttentionHeads || layer.folded.rows() != layer.in_width() ||
      layer.folded.cols() != layer.projected_width() || layer.self_coefficient.size() != heads ||
      layer.neighbour_coefficient.size() != heads || layer.self_norm.size() != heads ||
      layer.neighbour_norm.size() != heads ||
      (layer.bias.size() != 0 && layer.bias.size() != layer.out_width()))
    invalid(kAttentionKind, name,
            "derived tensors are stale or missing (call prepare() after setting weights)");
  const int32_t n = graph.node_count();
  if (n < 0 || graph.offsets.back() < 0 || static_cast<size_t>(graph.offsets.back()) != graph.sources.size())
    invalid(kAttentionKind, name, "attention graph offsets do not match its sources");
  check_shape(kAttentionKind, name, "input V", v.rows(), v.cols(), n, layer.in_width());
  check_shape(kAttentionKind, name, "output", out.rows(), out.cols(), n, layer.out_width());
  if (n == 0) return;

  const Index pw = layer.projected_width();
  const size_t nn = static_cast<size_t>(n), hh = static_cast<size_t>(heads);
  const bool own_projection = saved == nullptr || saved->projected == nullptr;
  const bool lipschitz = layer.variant == AttentionVariant::lgat;
  const int32_t tasks = task_count(n);
  const size_t per_task = attention_scratch_floats(hh, static_cast<size_t>(layer.weight.cols()), graph);
  const size_t needed = (own_projection ? nn * static_cast<size_t>(pw) : 0) + (lipschitz ? nn * hh : 0) +
                        static_cast<size_t>(tasks) * per_task;
  check_scratch(kAttentionKind, name, "GraphAttentionWorkspace", needed, workspace.scratch().capacity());

  float* cursor = workspace.scratch().data();
  float* projected = own_projection ? cursor : saved->projected;
  if (own_projection) cursor += nn * static_cast<size_t>(pw);
  float* norms = nullptr;
  if (lipschitz) {
    norms = cursor;
    cursor += nn * hh;
  }

  const AttentionParams params = attention_params(layer);
  float* pre = saved != nullptr ? saved->pre_activation : nullptr;
  ForwardJob job{&params,
                 &graph,
                 &layer.folded,
                 v.data(),
                 v.outerStride(),
                 layer.in_width(),
                 projected,
                 pw,
                 norms,
                 pre != nullptr ? pre : out.data(),
                 pre != nullptr ? layer.out_width() : out.outerStride(),
                 out.data(),
                 out.outerStride(),
                 layer.out_width(),
                 saved != nullptr ? saved->alpha : nullptr,
                 saved != nullptr ? saved->lipschitz_denominator : nullptr,
                 cursor,
                 per_task,
                 layer.activation,
                 n};
  SerialExecutor serial;
  Executor& run = executor != nullptr ? *executor : serial;
  run.run(tasks, project_task, &job);    // Z (and LGAT norms) for all rows first:
  run.run(tasks, aggregate_task, &job);  // every node reads its neighbours' rows
}

}  // namespace pleat::nn
