#pragma once
// The backward of attention_aggregate (graph_attention.h): what a trainer's
// autograd op calls next to the forward kernel. The GEMM Z = V [W | S | T],
// the bias and the activation stay outside (the framework differentiates
// them), so this is the gradient of
//   y_i^h = (P_h - Q_h) z_i^h + Q_h sum_j alpha_ij^h z_j^h     (heads merged)
// with respect to Z (the z columns and the two score columns of every head),
// the per-head coefficients P - Q and Q, and (LGAT) the attention-vector
// norms ||a_self||, ||a_neighbour||. docs/nn.md derives each term.
#include "nn/graph_attention.h"

namespace pleat::nn {

// Forward results the backward reads (row-major, contiguous):
//   projected: N x zstride, the forward's Z;
//   alpha: E x heads, saved by attention_aggregate;
//   norms, lipschitz_denominator: N x heads each (LGAT only; else null).
// grad_out: N x out (dL/dy of the merged, pre-bias output), row stride gstride.
// Writes (overwrites) grad_projected (N x zstride, same layout as Z),
// grad_self_coefficient and grad_neighbour_coefficient (heads each) and,
// for LGAT, grad_self_norm and grad_neighbour_norm (heads each; may be null
// otherwise). params.bias must be null: the bias belongs to the framework.
// Serial and in a fixed order: the result is deterministic.
template <typename Scalar>
void attention_aggregate_backward(const AttentionParamsT<Scalar>& params, const AttentionGraph& graph,
                                  const Scalar* projected, Index zstride, const Scalar* alpha,
                                  const Scalar* norms, const Scalar* lipschitz_denominator,
                                  const Scalar* grad_out, Index gstride, Scalar* grad_projected,
                                  Scalar* grad_self_coefficient, Scalar* grad_neighbour_coefficient,
                                  Scalar* grad_self_norm, Scalar* grad_neighbour_norm);

}  // namespace pleat::nn
