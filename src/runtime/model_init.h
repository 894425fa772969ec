#pragma once
// The initialiser: a freshly initialised model of the DESIGN §4 architecture
// for a skeleton and shape vector, the starting point of training (and a
// complete model for tests of the runtime). docs/models.md describes every
// choice; the result is deterministic for a seed on every platform that
// gives the same libm results for log/sqrt/cos/sin (the random stream and the
// mapping to uniform and normal numbers are our own).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "runtime/model.h"

namespace pleat::runtime {

struct ModelInitOptions {
  nn::AttentionVariant variant = nn::AttentionVariant::flexigat;  // every graph layer
  uint64_t seed = 1;
  int32_t window_frames = 8;  // m + 1
  double frame_rate = 30.0;
  int32_t default_top_k = 4;
  int32_t code_width = 128;                          // C: body code, garment code, GRU hidden width
  std::vector<int32_t> body_widths{128, 256, 128};   // body encoder MLP outputs
  int32_t body_vertex_stride = 1;                    // the encoder sees every k-th body vertex
  std::vector<int32_t> garment_widths{64, 64, 128};  // last must equal code_width
  int32_t heads = 4;                                 // every graph layer
  int32_t gru_layers = 3;
  std::vector<int32_t> blend_widths{64, 32, 3};               // last must be 3
  std::vector<int32_t> refinement_widths{64, 64, 32, 32, 3};  // last must be 3
  // The refinement's inputs (the paper's: the skinned garment's velocity,
  // normal and joint distances); Feature::fused_code adds F^t, the motion
  // history and the body (format version 5).
  std::vector<Feature> refinement_features{Feature::velocity, Feature::normal,
                                           Feature::posed_joint_distances};
  // The blend and refinement heads predict centimetres: cloth offsets of a
  // few cm are outputs of a few units, well inside what a tanh-fed identity
  // layer reaches, and the initial (random, ~0.3 unit) outputs move the
  // garment by only millimetres, so training starts from plain LBS.
  float blend_scale = 0.01f;
  // The body's own skinning as the starting point (decision 0004): an
  // untrained model skins like the body, training learns what differs.
  float skinning_prior = 1.0f;
  float skinning_prior_radius = 0.0f;  // Model::skinning_prior_radius
  float skinning_prior_floor = kDefaultSkinningPriorFloor;
  float refinement_scale = 0.01f;
  // h of the offset filter on the posed displacements, metres
  // (runtime/offset_filter.h); 0 = none, the paper's form.
  float offset_filter_length = 0.0f;
  std::string created;  // ISO 8601 stamp for the metadata; empty keeps the bytes reproducible
};

// Throws PLEAT_ERROR_INVALID_ARGUMENT naming the option (widths that do not
// chain, heads out of 1..16 or not dividing a hidden width) or the skeleton /
// shape entry at fault. The result has passed validate_model().
std::shared_ptr<Model> initialize_model(const ModelSkeleton& skeleton, const std::vector<ShapeEntry>& shape,
                                        const ModelInitOptions& options);

}  // namespace pleat::runtime
