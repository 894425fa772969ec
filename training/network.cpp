#include "network.h"

#include <algorithm>

#include "core/error.h"
#include "offset_filter_op.h"

namespace pleat::training {

torch::Tensor vertex_normals(const torch::Tensor& x, const torch::Tensor& triangles) {
  const torch::Tensor a = x.index_select(1, triangles.select(1, 0));
  const torch::Tensor b = x.index_select(1, triangles.select(1, 1));
  const torch::Tensor c = x.index_select(1, triangles.select(1, 2));
  const torch::Tensor cross = torch::cross(b - a, c - a, -1);  // twice the area: area weighting
  torch::Tensor n = torch::zeros_like(x);
  for (int k = 0; k < 3; ++k) n = n.index_add(1, triangles.select(1, k), cross);
  return n / n.norm(2, -1, true).clamp_min(1e-30);
}

BoundGarment::BoundGarment(const runtime::Model& model, std::shared_ptr<const Garment> garment,
                           const Body& body)
    : garment_(std::move(garment)), binding_(runtime::bind_inputs(model, *garment_, body)) {
  features_ = runtime::FrameFeatures(model, binding_->skeleton, binding_->body_of_model);
  body_input = to_tensor(binding_->body_input);
  garment_input = to_tensor(binding_->garment_input);
  if (binding_->prior.size() != 0) {
    prior = to_tensor(binding_->prior);
    prior_weights = torch::softmax(prior, -1);
  }
  rest = to_tensor(binding_->rest);
  const Triangles& t = garment_->rest.triangles;
  triangles =
      torch::from_blob(const_cast<int32_t*>(t.data()), {t.rows(), 3}, torch::kInt32).to(torch::kInt64);
}

const nn::AttentionGraph& BoundGarment::graph(int64_t copies) const {
  auto it = graphs_.find(copies);
  if (it != graphs_.end()) return it->second;
  const nn::AttentionGraph& one = binding_->graph;
  nn::AttentionGraph g;
  const int32_t n = one.node_count();
  g.max_degree = one.max_degree;
  g.offsets.assign(1, 0);
  for (int64_t c = 0; c < copies; ++c) {
    const int32_t shift = static_cast<int32_t>(c) * n, base = static_cast<int32_t>(g.sources.size());
    for (int32_t s : one.sources) g.sources.push_back(s + shift);
    for (int32_t i = 1; i <= n; ++i) g.offsets.push_back(base + one.offsets[i]);
  }
  return graphs_.emplace(copies, std::move(g)).first->second;
}

FrameInputs frame_inputs(const runtime::Model& model, const BoundGarment& bound,
                         const runtime::PoseSequence& poses, const std::vector<int64_t>& frames) {
  const runtime::Binding& b = bound.binding();
  const int64_t k = static_cast<int64_t>(frames.size()), joints = model.joint_count();
  const int64_t window = model.window_frames, width = model.motion_encoder.input_width();
  FrameInputs in;
  in.frames = frames;
  in.windows = torch::empty({k, window, width});
  in.skin = torch::empty({k, joints, 12});
  in.joints = torch::empty({k, joints, 3});
  in.heading = torch::empty({k, 3, 3});
  nn::MatrixRM window_x(window, width), skin(joints, 12), joint_positions(joints, 3);
  Quaternions pose(static_cast<size_t>(joints));
  Transforms pose_global(static_cast<size_t>(joints));
  SkinMatrices matrices(static_cast<size_t>(joints));
  for (int64_t i = 0; i < k; ++i) {
    const int64_t f = frames[static_cast<size_t>(i)];
    bound.features().motion_window(poses, f, window_x);
    runtime::normalize_rows(model.motion_normalization, window_x, 0, static_cast<int32_t>(window));
    bound.features().skinning_matrices(poses, f, pose, pose_global, b.rest_global, matrices, skin,
                                       joint_positions);
    const Eigen::Matrix<float, 3, 3, Eigen::RowMajor> h = bound.features().heading(poses, f).cast<float>();
    std::copy(window_x.data(), window_x.data() + window_x.size(), in.windows[i].data_ptr<float>());
    std::copy(skin.data(), skin.data() + skin.size(), in.skin[i].data_ptr<float>());
    std::copy(joint_positions.data(), joint_positions.data() + joint_positions.size(),
              in.joints[i].data_ptr<float>());
    std::copy(h.data(), h.data() + 9, in.heading[i].data_ptr<float>());
  }
  return in;
}

NetworkImpl::NetworkImpl(const runtime::Model& model) : spec_(model) {
  for (size_t i = 0; i < model.body_encoder.layers.size(); ++i) {
    const nn::Dense& d = model.body_encoder.layers[i];
    body_weights_.push_back(
        register_parameter("body_encoder_" + std::to_string(i) + "_weight", to_tensor(d.weight)));
    body_biases_.push_back(
        register_parameter("body_encoder_" + std::to_string(i) + "_bias",
                           d.bias.size() ? to_tensor(d.bias) : torch::zeros({d.out_width()})));
  }
  pool_weight_ = register_parameter("body_pool_weight", to_tensor(model.body_pool.weight));
  pool_bias_ =
      register_parameter("body_pool_bias", model.body_pool.bias.size() ? to_tensor(model.body_pool.bias)
                                                                       : torch::zeros({model.code_width()}));
  const auto graph_layers = [&](const runtime::GraphStack& s, const std::string& name) {
    std::vector<GraphAttention> out;
    for (size_t i = 0; i < s.layers.size(); ++i)
      out.push_back(register_module(name + "_" + std::to_string(i), GraphAttention(s.layers[i])));
    return out;
  };
  garment_ = graph_layers(model.garment_encoder, "garment_encoder");
  blend_ = graph_layers(model.blend, "blend");
  refinement_ = graph_layers(model.refinement, "refinement");
  for (size_t i = 0; i < model.motion_encoder.layers.size(); ++i) {
    const nn::GruLayer& l = model.motion_encoder.layers[i];
    const std::string at = "motion_encoder_" + std::to_string(i) + "_";
    gru_.push_back({register_parameter(at + "w_ih", to_tensor(l.w_ih)),
                    register_parameter(at + "w_hh", to_tensor(l.w_hh)),
                    register_parameter(at + "b_ih", to_tensor(l.b_ih)),
                    register_parameter(at + "b_hh", to_tensor(l.b_hh))});
  }
  skinning_weight_ = register_parameter("skinning_weight", to_tensor(model.skinning.weight));
  skinning_bias_ =
      register_parameter("skinning_bias", model.skinning.bias.size() ? to_tensor(model.skinning.bias)
                                                                     : torch::zeros({model.joint_count()}));
}

torch::Tensor NetworkImpl::stack(std::vector<GraphAttention>& layers, const torch::Tensor& x,
                                 const nn::AttentionGraph& graph) {
  torch::Tensor h = x;
  for (GraphAttention& l : layers) h = l->forward(h, graph, generic_);
  return h;
}

torch::Tensor NetworkImpl::body_code(const BoundGarment& bound) {
  torch::Tensor h = bound.body_input;
  for (size_t i = 0; i < body_weights_.size(); ++i) {
    const bool last = i + 1 == body_weights_.size();
    h = activate(torch::addmm(body_biases_[i], h, body_weights_[i]),
                 last ? spec_.body_encoder.output_activation : spec_.body_encoder.hidden_activation);
  }
  const torch::Tensor pooled = torch::cat({h.mean(0), std::get<0>(h.max(0))}).unsqueeze(0);
  return activate(torch::addmm(pool_bias_, pooled, pool_weight_), spec_.body_pool_activation);
}

torch::Tensor NetworkImpl::gru(const torch::Tensor& windows) {
  const int64_t k = windows.size(0), steps = windows.size(1), hidden = spec_.code_width();
  std::vector<torch::Tensor> h(gru_.size(), torch::zeros({k, hidden}));
  for (int64_t t = 0; t < steps; ++t) {
    torch::Tensor x = windows.select(1, t);
    for (size_t l = 0; l < gru_.size(); ++l) {
      const auto& [w_ih, w_hh, b_ih, b_hh] = gru_[l];
      const auto gi = torch::addmm(b_ih, x, w_ih).chunk(3, 1),
                 gh = torch::addmm(b_hh, h[l], w_hh).chunk(3, 1);
      const torch::Tensor r = torch::sigmoid(gi[0] + gh[0]), z = torch::sigmoid(gi[1] + gh[1]);
      const torch::Tensor n = torch::tanh(gi[2] + r * gh[2]);
      h[l] = (1 - z) * n + z * h[l];
      x = h[l];
    }
  }
  return h.back();
}

NetworkOutput NetworkImpl::forward(const BoundGarment& bound, const runtime::PoseSequence& poses,
                                   const std::vector<int64_t>& frames, runtime::Stage stage) {
  const bool refine = stage == runtime::Stage::refinement;
  const int64_t b = static_cast<int64_t>(frames.size()), n = bound.vertex_count();
  std::vector<int64_t> all = frames;
  if (refine)
    for (int64_t f : frames) all.push_back(std::max<int64_t>(f - 1, 0));
  const FrameInputs in = frame_inputs(spec_, bound, poses, all);
  const int64_t k = static_cast<int64_t>(all.size());

  const torch::Tensor code = body_code(bound);
  const torch::Tensor fused_static = stack(garment_, bound.garment_input, bound.graph(1)) * code;  // N x C
  const torch::Tensor q = gru(in.windows);                                                         // K x C
  const torch::Tensor fused = fused_static.unsqueeze(0) * q.unsqueeze(1);  // K x N x C
  torch::Tensor logits = torch::matmul(fused, skinning_weight_) + skinning_bias_;
  if (bound.prior.defined()) logits = logits + bound.prior;
  const torch::Tensor weights = torch::softmax(logits, -1);  // K x N x S
  // M̃ = M [T̄; 1] + M [B; 0] with M = Σ w_k S_k: the second term is the blend
  // shapes' posed displacement, which the offset filter smooths (runtime's order).
  const torch::Tensor blended = torch::bmm(weights, in.skin).view({k, n, 3, 4});
  const torch::Tensor rotation = blended.narrow(3, 0, 3);
  torch::Tensor skinned =
      torch::matmul(rotation, bound.rest.unsqueeze(0).expand({k, n, 3}).unsqueeze(-1)).squeeze(-1) +
      blended.select(3, 3);
  torch::Tensor blend;
  if (stage != runtime::Stage::skinning) {
    blend = spec_.blend_scale *
            stack(blend_, fused.reshape({k * n, fused.size(2)}), bound.graph(k)).view({k, n, 3});
    torch::Tensor displacement = torch::matmul(rotation, blend.unsqueeze(-1)).squeeze(-1);
    if (bound.binding().offset_filter)
      displacement = filter_offsets(displacement, *bound.binding().offset_filter);
    skinned = skinned + displacement;
  }

  NetworkOutput out;
  out.skinned = skinned.narrow(0, 0, b);
  out.weights = weights.narrow(0, 0, b);
  if (blend.defined()) out.blend = blend.narrow(0, 0, b);
  if (!refine) {
    out.positions = out.skinned;
    return out;
  }
  const torch::Tensor current = out.skinned, previous = skinned.narrow(0, b, b);
  std::vector<float> has_previous;
  for (int64_t f : frames) has_previous.push_back(f > 0 ? 1.0f : 0.0f);
  const torch::Tensor mask = torch::tensor(has_previous).view({b, 1, 1});
  const torch::Tensor heading = in.heading.narrow(0, 0, b);
  std::vector<torch::Tensor> columns;
  for (runtime::Feature f : spec_.refinement.features) {
    if (f == runtime::Feature::velocity) {
      columns.push_back(
          torch::bmm((current - previous) * static_cast<float>(spec_.frame_rate) * mask, heading));
    } else if (f == runtime::Feature::normal) {
      columns.push_back(torch::bmm(vertex_normals(current, bound.triangles), heading));
    } else if (f == runtime::Feature::fused_code) {
      columns.push_back(fused.narrow(0, 0, b));
    } else {  // posed_joint_distances
      columns.push_back((current.unsqueeze(2) - in.joints.narrow(0, 0, b).unsqueeze(1)).norm(2, -1));
    }
  }
  torch::Tensor x = torch::cat(columns, -1);
  if (!spec_.refinement.normalization.empty())
    x = (x - to_tensor(spec_.refinement.normalization.shift)) *
        to_tensor(spec_.refinement.normalization.scale);
  torch::Tensor delta = stack(refinement_, x.reshape({b * n, x.size(2)}), bound.graph(b)).view({b, n, 3});
  if (bound.binding().offset_filter) delta = filter_offsets(delta, *bound.binding().offset_filter);
  out.positions = current + spec_.refinement_scale * torch::bmm(delta, heading.transpose(1, 2));
  return out;
}

std::vector<torch::Tensor> NetworkImpl::encoder_parameters() const {
  std::vector<torch::Tensor> out(body_weights_.begin(), body_weights_.end());
  out.insert(out.end(), body_biases_.begin(), body_biases_.end());
  out.push_back(pool_weight_);
  out.push_back(pool_bias_);
  for (const GraphAttention& l : garment_)
    for (const torch::Tensor& p : l->parameters()) out.push_back(p);
  for (const auto& layer : gru_) out.insert(out.end(), layer.begin(), layer.end());
  return out;
}

std::shared_ptr<runtime::Model> NetworkImpl::to_model() const {
  auto m = std::make_shared<runtime::Model>(spec_);
  for (size_t i = 0; i < body_weights_.size(); ++i) {
    m->body_encoder.layers[i].weight = to_matrix(body_weights_[i]);
    m->body_encoder.layers[i].bias = to_row(body_biases_[i]);
  }
  m->body_pool.weight = to_matrix(pool_weight_);
  m->body_pool.bias = to_row(pool_bias_);
  for (size_t i = 0; i < garment_.size(); ++i) m->garment_encoder.layers[i] = garment_[i]->to_layer();
  for (size_t i = 0; i < blend_.size(); ++i) m->blend.layers[i] = blend_[i]->to_layer();
  for (size_t i = 0; i < refinement_.size(); ++i) m->refinement.layers[i] = refinement_[i]->to_layer();
  for (size_t i = 0; i < gru_.size(); ++i) {
    nn::GruLayer& l = m->motion_encoder.layers[i];
    l.w_ih = to_matrix(gru_[i][0]);
    l.w_hh = to_matrix(gru_[i][1]);
    l.b_ih = to_row(gru_[i][2]);
    l.b_hh = to_row(gru_[i][3]);
  }
  m->skinning.weight = to_matrix(skinning_weight_);
  m->skinning.bias = to_row(skinning_bias_);
  runtime::validate_model(*m);
  return m;
}

}  // namespace pleat::training
