#pragma once
// The runtime's network (runtime/model.h, docs/runtime.md) as a libtorch
// module: same parameters, same layout, same order of operations, so a
// trained module exports to a model file the runtime reproduces (the parity
// test holds them to 1e-4 of the garment's size). Graph layers use the
// custom attention op (attention_op.h). Skinning weights are the exact
// softmax over all joints (the runtime's top-k is an evaluation shortcut).
#include <torch/torch.h>

#include <map>
#include <memory>
#include <vector>

#include "attention_op.h"
#include "runtime/binding.h"
#include "runtime/frame_features.h"
#include "runtime/instance.h"
#include "runtime/model.h"
#include "tensors.h"

namespace pleat::training {

// A garment bound to a body for training: the runtime's binding inputs as
// tensors (constants: they are data, not parameters).
class BoundGarment {
 public:
  BoundGarment(const runtime::Model& model, std::shared_ptr<const Garment> garment, const Body& body);

  const runtime::Binding& binding() const { return *binding_; }
  const runtime::FrameFeatures& features() const { return features_; }
  const Garment& garment() const { return *garment_; }
  int64_t vertex_count() const { return rest.size(0); }
  // The attention graph repeated `copies` times (frames of a batch side by
  // side), cached.
  const nn::AttentionGraph& graph(int64_t copies) const;

  torch::Tensor body_input, garment_input, prior, rest;  // float32
  torch::Tensor prior_weights;  // N x S: softmax(prior), the weights the prior alone gives; undefined without
  torch::Tensor triangles;      // F x 3, int64

 private:
  std::shared_ptr<const Garment> garment_;
  std::unique_ptr<runtime::Binding> binding_;
  runtime::FrameFeatures features_;
  mutable std::map<int64_t, nn::AttentionGraph> graphs_;
};

// Per-frame network inputs of K frames of a pose sequence (FrameFeatures).
struct FrameInputs {
  torch::Tensor windows;  // K x window x motion input (normalised)
  torch::Tensor skin;     // K x S x 12: skinning matrices [R | t], row-major, model order
  torch::Tensor joints;   // K x S x 3: posed joint positions
  torch::Tensor heading;  // K x 3 x 3: H_t
  std::vector<int64_t> frames;
};
FrameInputs frame_inputs(const runtime::Model& model, const BoundGarment& bound,
                         const runtime::PoseSequence& poses, const std::vector<int64_t>& frames);

struct NetworkOutput {
  torch::Tensor positions;  // B x N x 3: the requested stage's result
  torch::Tensor skinned;    // B x N x 3: M̃ (blend shapes included when run)
  torch::Tensor weights;    // B x N x S: skinning weights
  torch::Tensor blend;      // B x N x 3: blend_scale B^t in rest space; undefined at the skinning stage
};

class NetworkImpl : public torch::nn::Module {
 public:
  explicit NetworkImpl(const runtime::Model& model);

  // Frames `frames` of `poses` up to `stage`. The refinement's velocities
  // need each frame's predecessor, evaluated in the same pass.
  NetworkOutput forward(const BoundGarment& bound, const runtime::PoseSequence& poses,
                        const std::vector<int64_t>& frames, runtime::Stage stage);

  // The trained parameters as a runtime model (validated).
  std::shared_ptr<runtime::Model> to_model() const;
  const runtime::Model& spec() const { return spec_; }

  // Graph layers through the generic index_add formulation instead of the
  // custom op (the benchmark's baseline).
  void set_generic_attention(bool generic) { generic_ = generic; }

  // Parameter groups (the schedule freezes the encoders).
  std::vector<torch::Tensor> encoder_parameters() const;

 private:
  torch::Tensor body_code(const BoundGarment& bound);
  torch::Tensor gru(const torch::Tensor& windows);
  torch::Tensor stack(std::vector<GraphAttention>& layers, const torch::Tensor& x,
                      const nn::AttentionGraph& graph);

  runtime::Model spec_;
  std::vector<torch::Tensor> body_weights_, body_biases_;
  torch::Tensor pool_weight_, pool_bias_;
  std::vector<GraphAttention> garment_, blend_, refinement_;
  std::vector<std::array<torch::Tensor, 4>> gru_;  // w_ih, w_hh, b_ih, b_hh
  torch::Tensor skinning_weight_, skinning_bias_;
  bool generic_ = false;
};
TORCH_MODULE(Network);

// Area-weighted unit vertex normals (zero where no face contributes), as
// core/geometry.h computes them. x: B x N x 3.
torch::Tensor vertex_normals(const torch::Tensor& x, const torch::Tensor& triangles);

}  // namespace pleat::training
