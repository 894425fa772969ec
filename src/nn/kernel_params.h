#pragma once
// What the network's per-instruction-set kernels (nn/kernels) take, as plain
// data: no Eigen, no inline functions. Their builds include this header and
// must not see anything the linker could merge across builds.
#include <cstdint>

namespace pleat::nn {

enum class ActivationKind : int32_t { identity = 0, tanh = 1, relu = 2, leaky_relu = 3, elu = 4 };

enum class HeadMerge : int32_t { concat = 0, mean = 1 };

constexpr int32_t kMaxAttentionHeads = 16;

// The fused attention aggregation (nn/graph_attention.h).
template <typename Scalar>
struct AttentionParamsT {
  int32_t heads = 1;
  int32_t head_width = 1;
  HeadMerge merge = HeadMerge::concat;
  bool lipschitz = false;  // lgat
  Scalar negative_slope = Scalar(0.2);
  Scalar lipschitz_epsilon = Scalar(1e-6);
  const Scalar* self_coefficient = nullptr;       // heads: P - Q
  const Scalar* neighbour_coefficient = nullptr;  // heads: Q
  const Scalar* self_norm = nullptr;              // heads: ||a_self||      (lipschitz only)
  const Scalar* neighbour_norm = nullptr;         // heads: ||a_neighbour|| (lipschitz only)
  const Scalar* bias = nullptr;                   // out width, or null
};

}  // namespace pleat::nn
