#include "attention_op.h"

#include "nn/graph_attention_backward.h"
#include "tensors.h"

namespace pleat::training {
namespace {

using torch::autograd::AutogradContext;
using torch::autograd::tensor_list;

template <typename Scalar>
nn::AttentionParamsT<Scalar> params_of(const torch::Tensor& self_coefficient,
                                       const torch::Tensor& neighbour_coefficient,
                                       const torch::Tensor& self_norm, const torch::Tensor& neighbour_norm,
                                       int64_t heads, int64_t head_width, nn::HeadMerge merge, bool lipschitz,
                                       double slope, double epsilon) {
  nn::AttentionParamsT<Scalar> p;
  p.heads = static_cast<int32_t>(heads);
  p.head_width = static_cast<int32_t>(head_width);
  p.merge = merge;
  p.lipschitz = lipschitz;
  p.negative_slope = static_cast<Scalar>(slope);
  p.lipschitz_epsilon = static_cast<Scalar>(epsilon);
  p.self_coefficient = self_coefficient.data_ptr<Scalar>();
  p.neighbour_coefficient = neighbour_coefficient.data_ptr<Scalar>();
  p.self_norm = lipschitz ? self_norm.data_ptr<Scalar>() : nullptr;
  p.neighbour_norm = lipschitz ? neighbour_norm.data_ptr<Scalar>() : nullptr;
  return p;
}

struct Settings {
  const nn::AttentionGraph* graph;
  int64_t heads, head_width;
  nn::HeadMerge merge;
  bool lipschitz;
  double slope, epsilon;
};

void save(AutogradContext* ctx, const Settings& s) {
  ctx->saved_data["graph"] = static_cast<int64_t>(reinterpret_cast<intptr_t>(s.graph));
  ctx->saved_data["heads"] = s.heads;
  ctx->saved_data["head_width"] = s.head_width;
  ctx->saved_data["merge"] = static_cast<int64_t>(s.merge);
  ctx->saved_data["lipschitz"] = s.lipschitz;
  ctx->saved_data["slope"] = s.slope;
  ctx->saved_data["epsilon"] = s.epsilon;
}

Settings load(AutogradContext* ctx) {
  return {
      reinterpret_cast<const nn::AttentionGraph*>(static_cast<intptr_t>(ctx->saved_data["graph"].toInt())),
      ctx->saved_data["heads"].toInt(),
      ctx->saved_data["head_width"].toInt(),
      static_cast<nn::HeadMerge>(ctx->saved_data["merge"].toInt()),
      ctx->saved_data["lipschitz"].toBool(),
      ctx->saved_data["slope"].toDouble(),
      ctx->saved_data["epsilon"].toDouble()};
}

class AggregateFunction : public torch::autograd::Function<AggregateFunction> {
 public:
  static torch::Tensor forward(AutogradContext* ctx, torch::Tensor z, torch::Tensor self_coefficient,
                               torch::Tensor neighbour_coefficient, torch::Tensor self_norm,
                               torch::Tensor neighbour_norm, Settings s) {
    z = z.contiguous();
    self_coefficient = self_coefficient.contiguous();
    neighbour_coefficient = neighbour_coefficient.contiguous();
    const int64_t n = z.size(0), heads = s.heads;
    const int64_t out_width = s.merge == nn::HeadMerge::concat ? heads * s.head_width : s.head_width;
    const auto options = z.options();
    torch::Tensor y = torch::empty({n, out_width}, options);
    torch::Tensor alpha = torch::empty({s.graph->edge_count(), heads}, options);
    torch::Tensor norms = torch::zeros({s.lipschitz ? n : 0, heads}, options);
    torch::Tensor divisors = torch::zeros({s.lipschitz ? n : 0, heads}, options);
    torch::Tensor scratch =
        torch::empty({static_cast<int64_t>(nn::attention_scratch_floats(
                         static_cast<size_t>(heads), static_cast<size_t>(heads * s.head_width), *s.graph))},
                     options);
    AT_DISPATCH_FLOATING_TYPES(z.scalar_type(), "pleat_attention_aggregate", [&] {
      const auto p = params_of<scalar_t>(self_coefficient, neighbour_coefficient, self_norm, neighbour_norm,
                                         heads, s.head_width, s.merge, s.lipschitz, s.slope, s.epsilon);
      if (s.lipschitz)
        nn::attention_node_norms(p, z.data_ptr<scalar_t>(), z.size(1), 0, static_cast<int32_t>(n),
                                 norms.data_ptr<scalar_t>());
      nn::attention_aggregate(
          p, *s.graph, z.data_ptr<scalar_t>(), z.size(1), s.lipschitz ? norms.data_ptr<scalar_t>() : nullptr,
          0, static_cast<int32_t>(n), y.data_ptr<scalar_t>(), out_width, alpha.data_ptr<scalar_t>(),
          scratch.data_ptr<scalar_t>(), s.lipschitz ? divisors.data_ptr<scalar_t>() : nullptr);
    });
    save(ctx, s);
    ctx->save_for_backward(
        {z, self_coefficient, neighbour_coefficient, self_norm, neighbour_norm, alpha, norms, divisors});
    return y;
  }

  static tensor_list backward(AutogradContext* ctx, tensor_list grad_outputs) {
    const Settings s = load(ctx);
    const auto saved = ctx->get_saved_variables();
    const torch::Tensor &z = saved[0], &self_coefficient = saved[1], &neighbour_coefficient = saved[2];
    const torch::Tensor &alpha = saved[5], &norms = saved[6], &divisors = saved[7];
    const torch::Tensor self_norm = saved[3].contiguous(), neighbour_norm = saved[4].contiguous();
    const torch::Tensor grad = grad_outputs[0].contiguous();
    torch::Tensor grad_z = torch::empty_like(z);
    torch::Tensor grad_self = torch::empty({s.heads}, z.options());
    torch::Tensor grad_neighbour = torch::empty({s.heads}, z.options());
    torch::Tensor grad_self_norm = torch::zeros({s.heads}, z.options());
    torch::Tensor grad_neighbour_norm = torch::zeros({s.heads}, z.options());
    AT_DISPATCH_FLOATING_TYPES(z.scalar_type(), "pleat_attention_aggregate_backward", [&] {
      const auto p = params_of<scalar_t>(self_coefficient, neighbour_coefficient, self_norm, neighbour_norm,
                                         s.heads, s.head_width, s.merge, s.lipschitz, s.slope, s.epsilon);
      nn::attention_aggregate_backward(
          p, *s.graph, z.data_ptr<scalar_t>(), z.size(1), alpha.data_ptr<scalar_t>(),
          s.lipschitz ? norms.data_ptr<scalar_t>() : nullptr,
          s.lipschitz ? divisors.data_ptr<scalar_t>() : nullptr, grad.data_ptr<scalar_t>(), grad.size(1),
          grad_z.data_ptr<scalar_t>(), grad_self.data_ptr<scalar_t>(), grad_neighbour.data_ptr<scalar_t>(),
          grad_self_norm.data_ptr<scalar_t>(), grad_neighbour_norm.data_ptr<scalar_t>());
    });
    return {grad_z,
            grad_self,
            grad_neighbour,
            s.lipschitz ? grad_self_norm : torch::Tensor(),
            s.lipschitz ? grad_neighbour_norm : torch::Tensor(),
            torch::Tensor()};
  }
};

}  // namespace

torch::Tensor attention_aggregate(const torch::Tensor& z, const torch::Tensor& self_coefficient,
                                  const torch::Tensor& neighbour_coefficient, const torch::Tensor& self_norm,
                                  const torch::Tensor& neighbour_norm, const nn::AttentionGraph& graph,
                                  int64_t heads, nn::HeadMerge merge, bool lipschitz, double negative_slope,
                                  double lipschitz_epsilon) {
  TORCH_CHECK(z.dim() == 2 && z.size(0) == graph.node_count(),
              "attention_aggregate: z must be N x (H d' + 2H)");
  TORCH_CHECK((z.size(1) - 2 * heads) % heads == 0 && z.size(1) > 2 * heads, "attention_aggregate: z has ",
              z.size(1), " columns, not H d' + 2H for ", heads, " heads");
  const int64_t head_width = (z.size(1) - 2 * heads) / heads;
  // Autograd wants defined tensors for every input: zeros stand in for the
  // norms GAT and FlexiGAT do not use.
  const torch::Tensor unused = torch::zeros({heads}, z.options());
  return AggregateFunction::apply(
      z, self_coefficient, neighbour_coefficient, lipschitz ? self_norm : unused,
      lipschitz ? neighbour_norm : unused,
      Settings{&graph, heads, head_width, merge, lipschitz, negative_slope, lipschitz_epsilon});
}

torch::Tensor attention_aggregate_generic(const torch::Tensor& z, const torch::Tensor& self_coefficient,
                                          const torch::Tensor& neighbour_coefficient,
                                          const torch::Tensor& self_norm, const torch::Tensor& neighbour_norm,
                                          const nn::AttentionGraph& graph, int64_t heads, nn::HeadMerge merge,
                                          bool lipschitz, double negative_slope, double lipschitz_epsilon) {
  const int64_t n = z.size(0), d = (z.size(1) - 2 * heads) / heads;
  const auto index = torch::TensorOptions().dtype(torch::kLong);
  std::vector<int64_t> dst_v, src_v;
  for (int32_t i = 0; i < n; ++i)
    for (int32_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e) {
      dst_v.push_back(i);
      src_v.push_back(graph.sources[e]);
    }
  const torch::Tensor dst = torch::tensor(dst_v, index), src = torch::tensor(src_v, index);
  const torch::Tensor values = z.narrow(1, 0, heads * d).reshape({n, heads, d});
  const torch::Tensor self_score = z.narrow(1, heads * d, heads),
                      neighbour_score = z.narrow(1, heads * d + heads, heads);
  torch::Tensor raw = self_score.index_select(0, dst) + neighbour_score.index_select(0, src);  // E x H
  if (lipschitz) {
    const torch::Tensor norms = values.norm(2, -1);  // N x H
    // max over each destination's neighbourhood of ||z_j||.
    const torch::Tensor largest = torch::zeros({n, heads}, z.options())
                                      .scatter_reduce(0, dst.unsqueeze(1).expand({-1, heads}),
                                                      norms.index_select(0, src), "amax", false);
    const torch::Tensor divisor = self_norm * norms + neighbour_norm * largest + lipschitz_epsilon;
    raw = raw / divisor.index_select(0, dst);
  }
  const torch::Tensor logits = torch::leaky_relu(raw, negative_slope);
  const torch::Tensor top =
      torch::full({n, heads}, -1e30, z.options())
          .scatter_reduce(0, dst.unsqueeze(1).expand({-1, heads}), logits, "amax", true);
  const torch::Tensor e = (logits - top.index_select(0, dst)).exp();
  const torch::Tensor sum = torch::zeros({n, heads}, z.options()).index_add(0, dst, e);
  const torch::Tensor alpha = e / sum.index_select(0, dst);
  const torch::Tensor weighted = torch::zeros({n, heads, d}, z.options())
                                     .index_add(0, dst, alpha.unsqueeze(-1) * values.index_select(0, src));
  const torch::Tensor y = self_coefficient.view({1, heads, 1}) * values +
                          neighbour_coefficient.view({1, heads, 1}) * weighted;  // N x H x d
  return merge == nn::HeadMerge::concat ? y.reshape({n, heads * d}) : y.mean(1);
}

torch::Tensor activate(const torch::Tensor& x, const nn::Activation& a) {
  switch (a.kind) {
    case nn::ActivationKind::identity: return x;
    case nn::ActivationKind::tanh: return torch::tanh(x);
    case nn::ActivationKind::relu: return torch::relu(x);
    case nn::ActivationKind::leaky_relu: return torch::leaky_relu(x, a.parameter);
    case nn::ActivationKind::elu: return torch::elu(x, a.parameter);
  }
  return x;
}

GraphAttentionImpl::GraphAttentionImpl(const nn::GraphAttentionLayer& layer) : spec_(layer) {
  weight = register_parameter("weight", to_tensor(layer.weight));
  attention = register_parameter("attention", to_tensor(layer.attention));
  const bool flexible = layer.variant == nn::AttentionVariant::flexigat;
  p = register_parameter("p", flexible ? to_tensor(layer.p) : torch::ones({layer.heads}), flexible);
  q = register_parameter("q", flexible ? to_tensor(layer.q) : torch::ones({layer.heads}), flexible);
  bias = register_parameter("bias",
                            layer.bias.size() ? to_tensor(layer.bias) : torch::zeros({layer.out_width()}));
}

torch::Tensor GraphAttentionImpl::forward(const torch::Tensor& v, const nn::AttentionGraph& graph,
                                          bool generic) {
  const int64_t heads = spec_.heads, d = weight.size(1) / heads;
  // Fold the attention vectors: S = W_h a_self,h and T = W_h a_neighbour,h per head.
  const torch::Tensor w = weight.view({weight.size(0), heads, d});
  const torch::Tensor s = (w * attention.narrow(1, 0, d).unsqueeze(0)).sum(-1);
  const torch::Tensor t = (w * attention.narrow(1, d, d).unsqueeze(0)).sum(-1);
  const torch::Tensor z = torch::mm(v, torch::cat({weight, s, t}, 1).to(v.dtype()));
  const bool lipschitz = spec_.variant == nn::AttentionVariant::lgat;
  const torch::Tensor self_norm = attention.narrow(1, 0, d).norm(2, 1).to(v.dtype());
  const torch::Tensor neighbour_norm = attention.narrow(1, d, d).norm(2, 1).to(v.dtype());
  const bool flexible = spec_.variant == nn::AttentionVariant::flexigat;
  const torch::Tensor self_coefficient =
      flexible ? (p - q).to(v.dtype()) : torch::zeros({heads}, v.options());
  const torch::Tensor neighbour_coefficient = flexible ? q.to(v.dtype()) : torch::ones({heads}, v.options());
  const auto aggregate = generic ? attention_aggregate_generic : attention_aggregate;
  const torch::Tensor y =
      aggregate(z, self_coefficient, neighbour_coefficient, self_norm, neighbour_norm, graph, heads,
                spec_.merge, lipschitz, spec_.negative_slope, spec_.lipschitz_epsilon);
  return activate(y + bias.to(v.dtype()), spec_.activation);
}

nn::GraphAttentionLayer GraphAttentionImpl::to_layer() const {
  nn::GraphAttentionLayer l = spec_;
  l.weight = to_matrix(weight);
  l.attention = to_matrix(attention);
  if (spec_.variant == nn::AttentionVariant::flexigat) {
    l.p = to_row(p);
    l.q = to_row(q);
  }
  l.bias = to_row(bias);
  l.prepare();
  return l;
}

}  // namespace pleat::training
