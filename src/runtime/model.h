#pragma once
// A loaded model (DESIGN §4): every architectural choice of the paper's
// network as data, plus the skeleton, shape vector and frame rate it was
// trained with. Immutable once built; shared by every instance bound to it.
//
// Data flow per frame t (docs/runtime.md has the exact feature definitions):
//   body code   b   = σ(body_pool([mean | max] over every k-th body vertex of body_encoder([β | Dis_i])))
//   garment     G   = garment_encoder(rest features)                      (N x C)
//   motion      q^t = motion_encoder(window of frame features)            (C)
//   fusion      F^t = G ⊙ b ⊙ q^t                                          (N x C)
//   weights     W^t = softmax(F^t · skinning.weight + skinning.bias + prior) (N x S)
//   blend       T^t = T̄ + blend_scale · blend(F^t)
//   skinning    M̃^t = LBS(T^t, joint transforms of frame t, W^t)
//   refinement  M^t = M̃^t + refinement_scale · refinement(features of M̃^t [, F^t])
// With offset_filter_length h > 0, what the blend shapes add to the skinned
// garment (LBS(T^t) − LBS(T̄)) and the refinement's displacement pass through
// the garment's offset filter (I + L_h)^{-1} (runtime/offset_filter.h).
#include <cstdint>
#include <string>
#include <vector>

#include "nn/dense.h"
#include "nn/graph_attention.h"
#include "nn/gru.h"
#include "nn/mlp.h"

namespace pleat::runtime {

using nn::Index;

// Per-vertex / per-frame input features. Each stack's input is the
// concatenation of its feature list, in order (widths in parentheses;
// S = joint count, |β| = shape count, C = code width).
enum class Feature : int32_t {
  shape = 0,                  // body encoder: β in the model's shape order (|β|)
  rest_joint_distances = 1,   // body / garment encoder: distances to the rest joints J(β) (S)
  rest_position = 2,          // garment encoder: rest position (3)
  rest_normal = 3,            // garment encoder: rest normal (3)
  joint_rotations_6d = 4,     // motion encoder: per joint, first two columns of its pose rotation (6 S)
  root_velocity = 5,          // motion encoder: root velocity, m/s, in frame t's heading frame (3)
  velocity = 6,               // refinement: (M̃^t − M̃^{t−1}) · frame rate in frame t's frame (3)
  normal = 7,                 // refinement: vertex normal of M̃^t (3)
  posed_joint_distances = 8,  // refinement: distances to the joints of frame t (S)
  // refinement: the vertex's row of F^t = G ⊙ b ⊙ q^t (C), the only way the
  // refinement sees the motion history and the body.
  fused_code = 9,
};
int32_t feature_width(Feature feature, int32_t joint_count, int32_t shape_count, int32_t code_width);
const char* feature_name(Feature feature);

// How the motion encoder sees time. Only `window` is implemented: every frame
// re-runs the GRU over its own window from a zero state (DESIGN §4).
enum class MotionMode : int32_t { window = 0 };

// (x − shift) ⊙ scale per input column; both empty = identity.
struct InputNormalization {
  nn::RowVector shift;
  nn::RowVector scale;
  bool empty() const { return shift.size() == 0 && scale.size() == 0; }
};

struct GraphStack {
  std::vector<Feature> features;  // input columns (garment encoder, refinement)
  InputNormalization normalization;
  std::vector<nn::GraphAttentionLayer> layers;  // prepare()d by the loader
  Index in_width() const { return layers.empty() ? 0 : layers.front().in_width(); }
  Index out_width() const { return layers.empty() ? 0 : layers.back().out_width(); }
};

struct ModelSkeleton {
  std::vector<std::string> joint_names;
  std::vector<int32_t> parents;  // -1 for the root; parents[j] < j
  int32_t joint_count() const { return static_cast<int32_t>(joint_names.size()); }
};

struct ShapeEntry {
  std::string name;
  float default_value = 0.0f;  // used when the bound body has no shape vector
};

// Settings of the frequency bands the model was trained with (metadata: the
// runtime splits with the bound garment's own bands).
struct ModelBands {
  double low_fraction = 1.0 / 30.0;
  double mid_fraction = 0.2;
  uint32_t projection = 0;  // PLEAT_PROJECTION_*
};

struct TrainingMetric {
  std::string name;
  double value = 0.0;
};

struct TrainingInfo {
  std::string dataset;
  std::string optimizer;  // "adamax"
  double learning_rate = 0.0;
  std::string schedule;  // "cosine"
  int64_t epochs = 0;
  int64_t seed = 0;
  std::string created;  // ISO 8601
  std::string generator;
  std::vector<TrainingMetric> metrics;
};

// The floor of the skinning prior's log(w + floor) in files that do not set
// one (format versions 1-3): a zero body weight stays finite.
constexpr float kDefaultSkinningPriorFloor = 1e-6f;

struct Model {
  std::string source;  // file it came from, for messages
  ModelSkeleton skeleton;
  std::vector<ShapeEntry> shape;
  double frame_rate = 30.0;   // poses must come at this rate
  int32_t window_frames = 8;  // m + 1
  MotionMode motion_mode = MotionMode::window;
  int32_t default_top_k = 4;  // joints per vertex at runtime; >= S means exact

  // Body encoder: per body vertex input = body_features, MLP, then
  // body_pool(tanh) over [mean | max] of the MLP outputs.
  std::vector<Feature> body_features;
  InputNormalization body_normalization;
  nn::Mlp body_encoder;
  nn::Dense body_pool;  // 2 * body_encoder.out_width() -> code width
  nn::Activation body_pool_activation = nn::Activation::tanh();
  // The encoder sees body vertices 0, k, 2k, ... only (k = this stride; 1 =
  // all, the paper's form): the pooled code needs a uniform share of the
  // body, not all of it, and training recomputes it every step.
  int32_t body_vertex_stride = 1;

  GraphStack garment_encoder;  // -> code width

  std::vector<Feature> motion_features;
  InputNormalization motion_normalization;
  nn::Gru motion_encoder;  // hidden width = code width

  nn::Dense skinning;  // code width -> S (softmax over joints)
  // Weight of the bound body's skinning as a prior on the logits:
  // logits += skinning_prior * log(w_body + 1e-6), w_body = the skin weights
  // of the body vertex nearest to each rest garment vertex (0 = none, the
  // paper's form). docs/decisions/0004-skinning-prior.md.
  float skinning_prior = 0.0f;
  // Its reach: body weights averaged within this radius (metres; 0 = the
  // nearest vertex alone), and the floor f of log(w + f). A prior that only
  // names the nearest vertex's joints puts every other joint at log(1e-6):
  // training can never move a skirt's hem from a thigh to the hips.
  float skinning_prior_radius = 0.0f;
  float skinning_prior_floor = kDefaultSkinningPriorFloor;

  GraphStack blend;  // code width -> 3
  float blend_scale = 1.0f;
  GraphStack refinement;  // refinement features -> 3
  float refinement_scale = 1.0f;
  // h, metres: the posed displacements of the blend shapes and of the
  // refinement pass through the garment's offset filter
  // (runtime/offset_filter.h); 0 = none.
  float offset_filter_length = 0.0f;

  ModelBands bands;
  TrainingInfo training;

  int32_t joint_count() const { return skeleton.joint_count(); }
  int32_t shape_count() const { return static_cast<int32_t>(shape.size()); }
  Index code_width() const { return body_pool.out_width(); }
};

// Whether the refinement's inputs include Feature::fused_code.
bool refinement_reads_code(const Model& model);

// Number of learned scalars (every weight, bias, attention vector, P, Q).
int64_t parameter_count(const Model& model);

// Throws pleat::Error(PLEAT_ERROR_FORMAT) naming `model.source` and the field
// at fault unless every width chains (feature lists -> first layers, stacks
// -> code width, skinning -> S, heads -> 3), the skeleton is parents-first
// with unique names, every parameter is finite and the scalar settings are
// in range. Prepares the graph layers (derived tensors).
void validate_model(Model& model);

}  // namespace pleat::runtime
