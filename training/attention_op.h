#pragma once
// The graph-attention layer of the runtime (nn/graph_attention.h) as a
// libtorch module. The projection Z = V [W | W a_self | W a_neighbour], P - Q,
// the attention-vector norms, the bias and the activation are ordinary
// torch operations; the aggregation in between is a custom autograd
// function whose forward is the runtime's kernel and whose backward is the
// hand-written one beside it (nn/graph_attention_backward.h). DESIGN §6
// measured generic index_add scatter at ~1 s per layer and batch; this op
// exists so the trainer does not pay that.
#include <torch/torch.h>

#include "nn/graph_attention.h"

namespace pleat::training {

// y (N x out, before bias) = attention_aggregate(z, ...). z: N x (H d' + 2H);
// self_coefficient (P - Q) and neighbour_coefficient (Q): [H]; self_norm and
// neighbour_norm: [H] (LGAT; else undefined tensors). float32 or float64,
// contiguous, CPU. `graph` must outlive the autograd graph.
torch::Tensor attention_aggregate(const torch::Tensor& z, const torch::Tensor& self_coefficient,
                                  const torch::Tensor& neighbour_coefficient, const torch::Tensor& self_norm,
                                  const torch::Tensor& neighbour_norm, const nn::AttentionGraph& graph,
                                  int64_t heads, nn::HeadMerge merge, bool lipschitz, double negative_slope,
                                  double lipschitz_epsilon);

// The same computation with generic torch operations (index_select,
// scatter-style index_add, a segment softmax through index_add): the
// baseline the custom op is benchmarked against, and a second opinion in tests.
torch::Tensor attention_aggregate_generic(const torch::Tensor& z, const torch::Tensor& self_coefficient,
                                          const torch::Tensor& neighbour_coefficient,
                                          const torch::Tensor& self_norm, const torch::Tensor& neighbour_norm,
                                          const nn::AttentionGraph& graph, int64_t heads, nn::HeadMerge merge,
                                          bool lipschitz, double negative_slope, double lipschitz_epsilon);

// One GAT / LGAT / FlexiGAT layer with trainable parameters, laid out as
// nn::GraphAttentionLayer (weight in x H d', attention H x 2d', p, q, bias).
class GraphAttentionImpl : public torch::nn::Module {
 public:
  // Copies the runtime layer's parameters (and its variant, merge, heads,
  // activation, slope, epsilon).
  explicit GraphAttentionImpl(const nn::GraphAttentionLayer& layer);
  // v: N x in on `graph` (which must outlive the autograd graph).
  torch::Tensor forward(const torch::Tensor& v, const nn::AttentionGraph& graph, bool generic = false);
  // The trained parameters back into a runtime layer (prepare()d).
  nn::GraphAttentionLayer to_layer() const;

  torch::Tensor weight, attention, p, q, bias;

 private:
  nn::GraphAttentionLayer spec_;  // variant, merge, heads, activation, constants
};
TORCH_MODULE(GraphAttention);

// Applies a runtime activation to a tensor.
torch::Tensor activate(const torch::Tensor& x, const nn::Activation& activation);

}  // namespace pleat::training
