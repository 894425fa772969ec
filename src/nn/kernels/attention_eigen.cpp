// The attention kernel: logits, softmax and the weighted sum per destination
// node, specialised at compile time by head count, variant and merge mode,
// and compiled once per instruction set (nn/kernels/eigen_renamed.h).
#include "nn/kernels/eigen_renamed.h"
// Only plain data from pleat (nn/kernel_params.h): nothing the linker
// could merge with the other build.
#include "nn/kernels/entry_points.h"

namespace pleat::nn::kernels {
namespace {

using Index = std::ptrdiff_t;

template <typename Scalar>
inline Scalar max_of(Scalar a, Scalar b) {  // std::max would be a symbol both builds share
  return a < b ? b : a;
}

template <typename Scalar>
using Packet = Eigen::Array<Scalar, 4, 1>;
// The widest float vector of this build: 8 lanes where AVX is compiled in
// (the weighted sum's blocks of 64-wide rows), else 4. Doubles stay at 4.
#ifdef EIGEN_VECTORIZE_AVX
template <typename Scalar>
constexpr int kWideLanes = sizeof(Scalar) == 4 ? 8 : 4;
#else
template <typename Scalar>
constexpr int kWideLanes = 4;
#endif
template <typename Scalar>
using ConstPacketMap = Eigen::Map<const Packet<Scalar>>;

// The weighted sum of one destination row when d' is a multiple of kLanes:
// the row is walked in blocks of four kLanes-Scalar vectors held in
// registers across all edges (no load/store of the output per edge). Same operation order per
// element as the scalar path: edges in CSR order (heads in order within an
// edge for mean), then the self term, then the bias.
template <typename Scalar, bool kConcat, int kLanes>
inline void accumulate_blocked(int32_t heads, Index d, int32_t degree, const int32_t* nb, const Scalar* z,
                               Index zstride, const Scalar* zi, const Scalar* a,
                               const Scalar* neighbour_coefficient, const Scalar* self_coefficient,
                               const Scalar* bias, Scalar* row) {
  using Vec = Eigen::Array<Scalar, kLanes, 1>;
  using ConstVecMap = Eigen::Map<const Vec>;
  const Index out_vectors = (kConcat ? heads * d : d) / kLanes;
  // Column offset in z and head of output vector u (concat: head = col / d;
  // mean: every head contributes, offset h*d added below).
  Index v = 0;
  for (; v + 4 <= out_vectors; v += 4) {
    Vec acc[4] = {Vec::Zero(), Vec::Zero(), Vec::Zero(), Vec::Zero()};
    int32_t head[4];
    for (int u = 0; u < 4; ++u) head[u] = kConcat ? static_cast<int32_t>((v + u) * kLanes / d) : 0;
    for (int32_t e = 0; e < degree; ++e) {
      const Scalar* zj = z + static_cast<Index>(nb[e]) * zstride + v * kLanes;
      const Scalar* ae = a + static_cast<Index>(e) * heads;
      if constexpr (kConcat) {
        if (head[0] == head[3]) {  // d' % (4 kLanes) == 0: one coefficient for the block
          const Scalar c = neighbour_coefficient[head[0]] * ae[head[0]];
          for (int u = 0; u < 4; ++u) acc[u] += c * ConstVecMap(zj + kLanes * u);
        } else {
          for (int u = 0; u < 4; ++u)
            acc[u] += (neighbour_coefficient[head[u]] * ae[head[u]]) * ConstVecMap(zj + kLanes * u);
        }
      } else {
        for (int32_t h = 0; h < heads; ++h) {
          const Scalar c = neighbour_coefficient[h] * ae[h];
          for (int u = 0; u < 4; ++u) acc[u] += c * ConstVecMap(zj + h * d + kLanes * u);
        }
      }
    }
    if (self_coefficient != nullptr) {
      const Scalar* zs = zi + v * kLanes;
      if constexpr (kConcat) {
        for (int u = 0; u < 4; ++u) acc[u] += self_coefficient[head[u]] * ConstVecMap(zs + kLanes * u);
      } else {
        for (int32_t h = 0; h < heads; ++h)
          for (int u = 0; u < 4; ++u) acc[u] += self_coefficient[h] * ConstVecMap(zs + h * d + kLanes * u);
      }
    }
    if (bias != nullptr)
      for (int u = 0; u < 4; ++u) acc[u] += ConstVecMap(bias + v * kLanes + kLanes * u);
    for (int u = 0; u < 4; ++u) Eigen::Map<Vec>(row + v * kLanes + kLanes * u) = acc[u];
  }
  for (; v < out_vectors; ++v) {
    Vec acc = Vec::Zero();
    const int32_t hv = kConcat ? static_cast<int32_t>(v * kLanes / d) : 0;
    for (int32_t e = 0; e < degree; ++e) {
      const Scalar* zj = z + static_cast<Index>(nb[e]) * zstride + v * kLanes;
      const Scalar* ae = a + static_cast<Index>(e) * heads;
      if constexpr (kConcat) {
        acc += (neighbour_coefficient[hv] * ae[hv]) * ConstVecMap(zj);
      } else {
        for (int32_t h = 0; h < heads; ++h)
          acc += (neighbour_coefficient[h] * ae[h]) * ConstVecMap(zj + h * d);
      }
    }
    if (self_coefficient != nullptr) {
      if constexpr (kConcat) {
        acc += self_coefficient[hv] * ConstVecMap(zi + v * kLanes);
      } else {
        for (int32_t h = 0; h < heads; ++h) acc += self_coefficient[h] * ConstVecMap(zi + v * kLanes + h * d);
      }
    }
    if (bias != nullptr) acc += ConstVecMap(bias + v * kLanes);
    Eigen::Map<Vec>(row + v * kLanes) = acc;
  }
}

// Attention coefficients of destination i for all its edges, written to
// a[e * heads + h]: raw logits s_h.v_i + t_h.v_j (LGAT: times 1 / divisor),
// LeakyReLU as max(x, 0) + slope * min(x, 0) with SIMD max/min (a scalar
// select compiles to a branch that mispredicts on every other edge), then a
// max-shifted softmax per head. Generic head count.
template <typename Scalar, bool kLipschitz>
inline void softmax_scalar(const AttentionParamsT<Scalar>& params, int32_t heads, int32_t i, int32_t degree,
                           const int32_t* nb, const Scalar* z, Index zstride, Index width,
                           const Scalar* norms, Scalar* a, Scalar* lipschitz_denominator) {
  const Scalar* self_score = z + static_cast<Index>(i) * zstride + width;
  Scalar inverse_denominator[kMaxAttentionHeads];
  if constexpr (kLipschitz) {
    Scalar largest[kMaxAttentionHeads];
    for (int32_t h = 0; h < heads; ++h) largest[h] = 0.0f;
    for (int32_t e = 0; e < degree; ++e) {
      const Scalar* nj = norms + static_cast<Index>(nb[e]) * heads;
      for (int32_t h = 0; h < heads; ++h) largest[h] = max_of(largest[h], nj[h]);
    }
    for (int32_t h = 0; h < heads; ++h) {
      const Scalar den = params.self_norm[h] * norms[static_cast<Index>(i) * heads + h] +
                         params.neighbour_norm[h] * largest[h] + params.lipschitz_epsilon;
      if (lipschitz_denominator != nullptr) lipschitz_denominator[static_cast<Index>(i) * heads + h] = den;
      inverse_denominator[h] = 1.0f / den;
    }
  }
  for (int32_t e = 0; e < degree; ++e) {
    const Scalar* t = z + static_cast<Index>(nb[e]) * zstride + width + heads;
    Scalar* ae = a + static_cast<Index>(e) * heads;
    for (int32_t h = 0; h < heads; ++h) {
      if constexpr (kLipschitz)
        ae[h] = (self_score[h] + t[h]) * inverse_denominator[h];
      else
        ae[h] = self_score[h] + t[h];
    }
  }
  const Scalar slope = params.negative_slope;
  Eigen::Map<Eigen::Array<Scalar, Eigen::Dynamic, 1>> block(a, static_cast<Index>(degree) * heads);
  block = block.max(0.0f) + slope * block.min(0.0f);
  Scalar largest[kMaxAttentionHeads];
  for (int32_t h = 0; h < heads; ++h) largest[h] = a[h];
  for (int32_t e = 1; e < degree; ++e)
    for (int32_t h = 0; h < heads; ++h) largest[h] = max_of(largest[h], a[e * heads + h]);
  for (int32_t e = 0; e < degree; ++e)
    for (int32_t h = 0; h < heads; ++h) a[e * heads + h] -= largest[h];
  block = block.exp();
  Scalar inverse_sum[kMaxAttentionHeads];
  for (int32_t h = 0; h < heads; ++h) inverse_sum[h] = 0.0f;
  for (int32_t e = 0; e < degree; ++e)
    for (int32_t h = 0; h < heads; ++h) inverse_sum[h] += a[e * heads + h];
  for (int32_t h = 0; h < heads; ++h) inverse_sum[h] = 1.0f / inverse_sum[h];
  for (int32_t e = 0; e < degree; ++e)
    for (int32_t h = 0; h < heads; ++h) a[e * heads + h] *= inverse_sum[h];
}

// The same with kPackets * 4 heads, one packet per 4 heads and edge.
template <typename Scalar, int kPackets, bool kLipschitz>
inline void softmax_packets(const AttentionParamsT<Scalar>& params, int32_t i, int32_t degree,
                            const int32_t* nb, const Scalar* z, Index zstride, Index width,
                            const Scalar* norms, Scalar* a, Scalar* lipschitz_denominator) {
  constexpr int kHeads = 4 * kPackets;
  const Scalar* self_score = z + static_cast<Index>(i) * zstride + width;
  Packet<Scalar> self[kPackets], inverse_denominator[kPackets], largest[kPackets], sum[kPackets];
  for (int p = 0; p < kPackets; ++p) self[p] = ConstPacketMap<Scalar>(self_score + 4 * p);
  if constexpr (kLipschitz) {
    for (int p = 0; p < kPackets; ++p) largest[p] = Packet<Scalar>::Zero();
    for (int32_t e = 0; e < degree; ++e)
      for (int p = 0; p < kPackets; ++p)
        largest[p] =
            largest[p].max(ConstPacketMap<Scalar>(norms + static_cast<Index>(nb[e]) * kHeads + 4 * p));
    for (int p = 0; p < kPackets; ++p) {
      const Packet<Scalar> den = ConstPacketMap<Scalar>(params.self_norm + 4 * p) *
                                     ConstPacketMap<Scalar>(norms + static_cast<Index>(i) * kHeads + 4 * p) +
                                 ConstPacketMap<Scalar>(params.neighbour_norm + 4 * p) * largest[p] +
                                 params.lipschitz_epsilon;
      if (lipschitz_denominator != nullptr)
        Eigen::Map<Packet<Scalar>>(lipschitz_denominator + static_cast<Index>(i) * kHeads + 4 * p) = den;
      inverse_denominator[p] = den.inverse();
    }
  }
  const Scalar slope = params.negative_slope;
  for (int p = 0; p < kPackets; ++p)
    largest[p] = Packet<Scalar>::Constant(-Eigen::NumTraits<Scalar>::infinity());
  for (int32_t e = 0; e < degree; ++e) {
    const Scalar* t = z + static_cast<Index>(nb[e]) * zstride + width + kHeads;
    for (int p = 0; p < kPackets; ++p) {
      Packet<Scalar> x = self[p] + ConstPacketMap<Scalar>(t + 4 * p);
      if constexpr (kLipschitz) x *= inverse_denominator[p];
      x = x.max(0.0f) + slope * x.min(0.0f);
      Eigen::Map<Packet<Scalar>>(a + e * kHeads + 4 * p) = x;
      largest[p] = largest[p].max(x);
    }
  }
  for (int p = 0; p < kPackets; ++p) sum[p] = Packet<Scalar>::Zero();
  int32_t e = 0;
  if constexpr (kPackets == 1 && kWideLanes<Scalar> == 8) {
    // Four heads and 8-lane vectors: the exponentials of two edges at once.
    using Pair = Eigen::Array<Scalar, 8, 1>;
    Pair shift, pair_sum = Pair::Zero();
    for (int k = 0; k < 8; ++k) shift[k] = largest[0][k % 4];
    for (; e + 2 <= degree; e += 2) {
      Eigen::Map<Pair> x(a + e * kHeads);
      x = (x - shift).exp();
      pair_sum += x;
    }
    sum[0] = pair_sum.template head<4>() + pair_sum.template tail<4>();
  }
  for (; e < degree; ++e)
    for (int p = 0; p < kPackets; ++p) {
      Eigen::Map<Packet<Scalar>> x(a + e * kHeads + 4 * p);
      x = (x - largest[p]).exp();
      sum[p] += x;
    }
  for (int p = 0; p < kPackets; ++p) sum[p] = sum[p].inverse();
  for (int32_t e = 0; e < degree; ++e)
    for (int p = 0; p < kPackets; ++p) Eigen::Map<Packet<Scalar>>(a + e * kHeads + 4 * p) *= sum[p];
}

// Logits, softmax and the weighted sum for destination nodes [begin, end).
// kHeads > 0 fixes the head count at compile time (the per-head loops unroll
// and the logits of one edge become one SIMD vector); 0 reads it at run time.
// Lipschitz and the merge mode are template parameters too, so the inner
// loops carry no branches.
template <typename Scalar, int kHeads, bool kLipschitz, bool kConcat>
void aggregate_nodes(const AggregateCall<Scalar>& call) {
  const AttentionParamsT<Scalar>& params = *call.params;
  const Scalar* z = call.z;
  const Index zstride = call.zstride;
  const Scalar* norms = call.norms;
  Scalar* out = call.out;
  const Index ostride = call.ostride;
  Scalar* alpha = call.alpha;
  Scalar* scratch = call.scratch;
  Scalar* lipschitz_denominator = call.lipschitz_denominator;
  const int32_t heads = kHeads > 0 ? kHeads : params.heads;
  const Index d = params.head_width;
  const Index width = static_cast<Index>(heads) * d;  // columns of z holding z_j
  const Index out_width = kConcat ? width : d;
  const Scalar head_scale = kConcat ? 1.0f : 1.0f / static_cast<Scalar>(heads);
  const int32_t* offsets = call.offsets;
  const int32_t* sources = call.sources;
  Scalar* head_rows = scratch;  // heads * d' (mean, generic d'); then max_degree * heads (alpha)

  // Per-head coefficients: Q (times 1/H for mean) on alpha, (P - Q) on z_i.
  Scalar neighbour_coefficient[kMaxAttentionHeads], self_coefficient[kMaxAttentionHeads];
  bool has_self_term = false;
  for (int32_t h = 0; h < heads; ++h) {
    neighbour_coefficient[h] = params.neighbour_coefficient[h] * head_scale;
    self_coefficient[h] = params.self_coefficient[h] * head_scale;
    has_self_term = has_self_term || self_coefficient[h] != 0.0f;
  }

  for (int32_t i = call.begin; i < call.end; ++i) {
    Scalar* __restrict row = out + static_cast<Index>(i) * ostride;
    const int32_t first = offsets[i];
    const int32_t degree = offsets[i + 1] - first;
    const int32_t* __restrict nb = sources + first;
    if (degree == 0) {  // only a hand-built graph without self loops gets here
      for (Index k = 0; k < out_width; ++k) row[k] = params.bias != nullptr ? params.bias[k] : 0.0f;
      continue;
    }
    const Scalar* zi = z + static_cast<Index>(i) * zstride;
    Scalar* __restrict a = alpha != nullptr ? alpha + static_cast<Index>(first) * heads : scratch + width;

    if constexpr (kHeads > 0 && kHeads % 4 == 0) {
      // Heads in SIMD lanes: one edge's logits are kHeads / 4 packets.
      softmax_packets<Scalar, kHeads / 4, kLipschitz>(params, i, degree, nb, z, zstride, width, norms, a,
                                                      lipschitz_denominator);
    } else {
      softmax_scalar<Scalar, kLipschitz>(params, heads, i, degree, nb, z, zstride, width, norms, a,
                                         lipschitz_denominator);
    }

    // y_i = sum_j Q alpha_ij z_j + (P - Q) z_i + bias, in that order.
    if (d % 4 == 0) {
      if (kWideLanes < Scalar >> 4 && d % kWideLanes<Scalar> == 0)
        accumulate_blocked<Scalar, kConcat, kWideLanes<Scalar>>(
            heads, d, degree, nb, z, zstride, zi, a, neighbour_coefficient,
            has_self_term ? self_coefficient : nullptr, params.bias, row);
      else
        accumulate_blocked<Scalar, kConcat, 4>(heads, d, degree, nb, z, zstride, zi, a, neighbour_coefficient,
                                               has_self_term ? self_coefficient : nullptr, params.bias, row);
    } else if (!kConcat && d < 4 && (heads - 1) * d + 4 <= zstride) {
      // Mean of narrow heads (the xyz output layers, d' = 3): one packet per
      // head, lanes past d' read the next columns of the same Z row and are
      // dropped. Same per-element order as the generic path below.
      Packet<Scalar> acc[kMaxAttentionHeads];
      for (int32_t h = 0; h < heads; ++h) acc[h] = Packet<Scalar>::Zero();
      for (int32_t e = 0; e < degree; ++e) {
        const Scalar* zj = z + static_cast<Index>(nb[e]) * zstride;
        const Scalar* ae = a + static_cast<Index>(e) * heads;
        for (int32_t h = 0; h < heads; ++h)
          acc[h] += (neighbour_coefficient[h] * ae[h]) * ConstPacketMap<Scalar>(zj + h * d);
      }
      if (has_self_term)
        for (int32_t h = 0; h < heads; ++h)
          acc[h] += self_coefficient[h] * ConstPacketMap<Scalar>(zi + h * d);
      for (int32_t h = 1; h < heads; ++h) acc[0] += acc[h];
      for (Index k = 0; k < d; ++k) row[k] = acc[0][k] + (params.bias != nullptr ? params.bias[k] : 0.0f);
    } else {
      // Generic d': per-head accumulators (the row itself for concat), so each
      // output element's dependency chain is one add per edge, not per
      // edge and head; mean sums the heads at the end.
      Scalar* __restrict acc = kConcat ? row : head_rows;
      for (Index k = 0; k < width; ++k) acc[k] = 0.0f;
      for (int32_t e = 0; e < degree; ++e) {
        const Scalar* __restrict zj = z + static_cast<Index>(nb[e]) * zstride;
        const Scalar* ae = a + static_cast<Index>(e) * heads;
        for (int32_t h = 0; h < heads; ++h) {
          const Scalar c = neighbour_coefficient[h] * ae[h];
          for (Index k = 0; k < d; ++k) acc[h * d + k] += c * zj[h * d + k];
        }
      }
      if (has_self_term)
        for (int32_t h = 0; h < heads; ++h)
          for (Index k = 0; k < d; ++k) acc[h * d + k] += self_coefficient[h] * zi[h * d + k];
      if constexpr (!kConcat) {
        for (Index k = 0; k < d; ++k) {
          Scalar sum = acc[k];
          for (int32_t h = 1; h < heads; ++h) sum += acc[h * d + k];
          row[k] = sum;
        }
      }
      if (params.bias != nullptr)
        for (Index k = 0; k < out_width; ++k) row[k] += params.bias[k];
    }
  }
}

template <typename Scalar, int kHeads>
void aggregate_dispatch(const AggregateCall<Scalar>& call) {
  const bool concat = call.params->merge == HeadMerge::concat;
  if (call.params->lipschitz) {
    if (concat)
      aggregate_nodes<Scalar, kHeads, true, true>(call);
    else
      aggregate_nodes<Scalar, kHeads, true, false>(call);
  } else {
    if (concat)
      aggregate_nodes<Scalar, kHeads, false, true>(call);
    else
      aggregate_nodes<Scalar, kHeads, false, false>(call);
  }
}

template <typename Scalar>
void aggregate(const AggregateCall<Scalar>& call) {
  switch (call.params->heads) {
    case 1: return aggregate_dispatch<Scalar, 1>(call);
    case 2: return aggregate_dispatch<Scalar, 2>(call);
    case 4: return aggregate_dispatch<Scalar, 4>(call);
    case 8: return aggregate_dispatch<Scalar, 8>(call);
    default: return aggregate_dispatch<Scalar, 0>(call);
  }
}

}  // namespace

void PLEAT_KERNEL_ENTRY(attention_aggregate)(const AggregateCall<float>& call) {
  aggregate(call);
}

void PLEAT_KERNEL_ENTRY(attention_aggregate)(const AggregateCall<double>& call) {
  aggregate(call);
}

}  // namespace pleat::nn::kernels
