#include "nn/graph_attention_backward.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace pleat::nn {
namespace {

// dL/dz_j += dL/d||z_j^h|| z_j^h / ||z_j^h|| (LGAT's divisor reads the norms).
template <typename Scalar>
void add_norm_gradients(const std::vector<Scalar>& grad_norm, const Scalar* norms, const Scalar* projected,
                        Index zstride, int32_t n, int32_t heads, Index d, Scalar* grad_projected) {
  for (int32_t j = 0; j < n; ++j)
    for (int32_t h = 0; h < heads; ++h) {
      const Scalar norm = norms[static_cast<Index>(j) * heads + h];
      const Scalar gn = grad_norm[static_cast<size_t>(j) * heads + h];
      if (norm <= 0 || gn == 0) continue;
      const Scalar* zj = projected + static_cast<Index>(j) * zstride + h * d;
      Scalar* dzj = grad_projected + static_cast<Index>(j) * zstride + h * d;
      for (Index k = 0; k < d; ++k) dzj[k] += gn * zj[k] / norm;
    }
}

}  // namespace

template <typename Scalar>
void attention_aggregate_backward(const AttentionParamsT<Scalar>& params, const AttentionGraph& graph,
                                  const Scalar* projected, Index zstride, const Scalar* alpha,
                                  const Scalar* norms, const Scalar* lipschitz_denominator,
                                  const Scalar* grad_out, Index gstride, Scalar* grad_projected,
                                  Scalar* grad_self_coefficient, Scalar* grad_neighbour_coefficient,
                                  Scalar* grad_self_norm, Scalar* grad_neighbour_norm) {
  if (params.bias != nullptr)
    invalid("graph attention backward", "attention_aggregate_backward", "params.bias must be null");
  const int32_t heads = params.heads, n = graph.node_count();
  const Index d = params.head_width, width = static_cast<Index>(heads) * d;
  const bool concat = params.merge == HeadMerge::concat;
  const bool lipschitz = params.lipschitz;
  const Scalar scale = concat ? Scalar(1) : Scalar(1) / static_cast<Scalar>(heads);
  const Scalar slope = params.negative_slope;
  std::fill(grad_projected, grad_projected + static_cast<size_t>(n) * static_cast<size_t>(zstride),
            Scalar(0));
  for (int32_t h = 0; h < heads; ++h) {
    grad_self_coefficient[h] = 0;
    grad_neighbour_coefficient[h] = 0;
    if (lipschitz) grad_self_norm[h] = grad_neighbour_norm[h] = 0;
  }
  // dL/d||z_j^h|| (LGAT), turned into dL/dz_j at the end.
  std::vector<Scalar> grad_norm(lipschitz ? static_cast<size_t>(n) * heads : 0, Scalar(0));
  std::vector<Scalar> grad_alpha(static_cast<size_t>(std::max(graph.max_degree, 0)));

  for (int32_t i = 0; i < n; ++i) {
    const int32_t first = graph.offsets[i], degree = graph.offsets[i + 1] - first;
    if (degree == 0) continue;
    const int32_t* nb = graph.sources.data() + first;
    const Scalar* g_row = grad_out + static_cast<Index>(i) * gstride;
    const Scalar* zi_row = projected + static_cast<Index>(i) * zstride;
    Scalar* dzi_row = grad_projected + static_cast<Index>(i) * zstride;
    for (int32_t h = 0; h < heads; ++h) {
      const Scalar* g = g_row + (concat ? h * d : 0);
      const Scalar* zi = zi_row + h * d;
      const Scalar neighbour = params.neighbour_coefficient[h] * scale;
      const Scalar self = params.self_coefficient[h] * scale;
      // Self term (P - Q) z_i.
      Scalar g_dot_zi = 0;
      for (Index k = 0; k < d; ++k) {
        dzi_row[h * d + k] += self * g[k];
        g_dot_zi += g[k] * zi[k];
      }
      grad_self_coefficient[h] += scale * g_dot_zi;
      // Weighted sum Q sum_j alpha_ij z_j.
      Scalar weighted = 0;  // sum_j alpha_ij dL/dalpha_ij
      for (int32_t e = 0; e < degree; ++e) {
        const Scalar a = alpha[static_cast<Index>(first + e) * heads + h];
        const Scalar* zj = projected + static_cast<Index>(nb[e]) * zstride + h * d;
        Scalar* dzj = grad_projected + static_cast<Index>(nb[e]) * zstride + h * d;
        Scalar g_dot_zj = 0;
        for (Index k = 0; k < d; ++k) {
          g_dot_zj += g[k] * zj[k];
          dzj[k] += neighbour * a * g[k];
        }
        grad_neighbour_coefficient[h] += scale * a * g_dot_zj;
        grad_alpha[e] = neighbour * g_dot_zj;
        weighted += a * grad_alpha[e];
      }
      // Softmax, LeakyReLU, the two score columns (and LGAT's divisor).
      const Scalar self_score = zi_row[width + h];
      const Scalar inverse =
          lipschitz ? Scalar(1) / lipschitz_denominator[static_cast<Index>(i) * heads + h] : Scalar(1);
      Scalar grad_divisor = 0;
      for (int32_t e = 0; e < degree; ++e) {
        const Scalar a = alpha[static_cast<Index>(first + e) * heads + h];
        const Scalar grad_logit = a * (grad_alpha[e] - weighted);
        const Scalar raw = self_score + projected[static_cast<Index>(nb[e]) * zstride + width + heads + h];
        const Scalar u = raw * inverse;
        const Scalar grad_u = grad_logit * (u > 0 ? Scalar(1) : slope);
        const Scalar grad_raw = grad_u * inverse;
        dzi_row[width + h] += grad_raw;
        grad_projected[static_cast<Index>(nb[e]) * zstride + width + heads + h] += grad_raw;
        if (lipschitz) grad_divisor -= grad_u * u * inverse;  // u = raw / c: du/dc = -u / c
      }
      if (lipschitz) {
        // c = ||a_self|| ||z_i|| + ||a_neighbour|| max_k ||z_k|| + eps; the
        // max goes to its first neighbour in CSR order.
        int32_t largest = nb[0];
        for (int32_t e = 1; e < degree; ++e)
          if (norms[static_cast<Index>(nb[e]) * heads + h] > norms[static_cast<Index>(largest) * heads + h])
            largest = nb[e];
        const Scalar own = norms[static_cast<Index>(i) * heads + h];
        const Scalar top = norms[static_cast<Index>(largest) * heads + h];
        grad_self_norm[h] += grad_divisor * own;
        grad_neighbour_norm[h] += grad_divisor * top;
        grad_norm[static_cast<size_t>(i) * heads + h] += grad_divisor * params.self_norm[h];
        grad_norm[static_cast<size_t>(largest) * heads + h] += grad_divisor * params.neighbour_norm[h];
      }
    }
  }
  if (lipschitz) add_norm_gradients(grad_norm, norms, projected, zstride, n, heads, d, grad_projected);
}

template void attention_aggregate_backward(const AttentionParamsT<float>&, const AttentionGraph&,
                                           const float*, Index, const float*, const float*, const float*,
                                           const float*, Index, float*, float*, float*, float*, float*);
template void attention_aggregate_backward(const AttentionParamsT<double>&, const AttentionGraph&,
                                           const double*, Index, const double*, const double*, const double*,
                                           const double*, Index, double*, double*, double*, double*, double*);

}  // namespace pleat::nn
