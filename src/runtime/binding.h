#pragma once
// What binding a model to a garment and a body derives before any network
// runs (docs/runtime.md, "Binding"): the joint map, the rest joints J(β), the
// normalised inputs of the body and garment encoders, the skinning prior, the
// attention graph and the offset filter. The Instance runs the encoders on
// them once; the trainer runs them every step (their weights learn) from the
// same inputs.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "body/body.h"
#include "garment/garment.h"
#include "nn/graph_attention.h"
#include "runtime/model.h"
#include "runtime/offset_filter.h"

namespace pleat::runtime {

struct Binding {
  std::vector<int32_t> body_of_model;  // model joint -> body joint (poses come in body order)
  std::vector<int32_t> model_of_body;  // its inverse
  Skeleton skeleton;                   // the body's, body order
  Transforms rest_global;              // body order
  Points3d rest_joints;                // J(β), model order
  nn::MatrixRM body_input;             // every k-th body vertex x body-encoder input, normalised
  nn::MatrixRM garment_input;          // garment vertices x garment-encoder input, normalised
  nn::MatrixRM prior;                  // N x S: skinning_prior * log(w + floor); empty without a prior
  nn::AttentionGraph graph;            // mesh edges + self loops
  nn::MatrixRM rest;                   // N x 3: T̄ (float)
  std::unique_ptr<OffsetFilter> offset_filter;  // null when the model's offset_filter_length is 0
};

// Throws PLEAT_ERROR_INVALID_ARGUMENT when the body cannot drive the model:
// joint count, a model joint missing from the body, parents that differ, a
// shape entry the model reads that the body lacks (messages name them).
// Heap-allocated because FrameFeatures keeps a pointer to its skeleton.
std::unique_ptr<Binding> bind_inputs(const Model& model, const Garment& garment, const Body& body);

// (x - shift) * scale on rows [begin, end) of a feature matrix.
void normalize_rows(const InputNormalization& normalization, nn::MatrixRM& x, int32_t begin, int32_t end);

}  // namespace pleat::runtime
