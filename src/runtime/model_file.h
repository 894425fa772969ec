#pragma once
// The model file (schema/model.fbs, docs/models.md): written atomically;
// loading runs the FlatBuffers verifier, then checks every field (presence,
// tensor shapes, enum ranges) and finally validate_model(), so a loaded Model
// is ready for an Instance.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "runtime/model.h"

namespace pleat::runtime {

// The newest format version this build reads; files with a larger one are
// refused with PLEAT_ERROR_UNSUPPORTED_VERSION. A file is written with the
// lowest version that reads it correctly (model_format_version), so models
// that use nothing new stay readable by older builds.
//   1: the first format.
//   2: body_vertex_stride > 1.
//   3: offset_filter_length > 0.
//   4: skinning_prior_radius > 0 or a skinning_prior_floor of its own.
//   5: the refinement reads the fused code (Feature::fused_code).
constexpr uint32_t kModelFormatVersion = 5;
uint32_t model_format_version(const Model& model);

// Caps checked before anything is allocated from a file's counts.
constexpr int32_t kMaxModelJoints = 1024;
constexpr int32_t kMaxModelShapeEntries = 1024;
constexpr int32_t kMaxStackLayers = 64;  // per MLP, graph stack or GRU
constexpr int32_t kMaxStackFeatures = 16;
constexpr int32_t kMaxBodyVertexStride = 4096;
constexpr float kMaxOffsetFilterLength = 1.0f;   // metres
constexpr float kMaxSkinningPriorRadius = 1.0f;  // metres

std::vector<uint8_t> serialize_model(const Model& model);
// Atomic: the file appears complete or not at all. Throws PLEAT_ERROR_IO.
void save_model(const Model& model, const std::string& path);

// True if the file starts like a model file (identifier PLMD).
bool is_model_file(const std::string& path);

// Throws PLEAT_ERROR_FORMAT (corrupt, truncated, inconsistent: the message
// names `source` and the field, layer or tensor) or
// PLEAT_ERROR_UNSUPPORTED_VERSION (written by a newer pleat). `data` need not
// be aligned. The result has passed validate_model().
std::shared_ptr<Model> deserialize_model(const uint8_t* data, size_t size, const std::string& source);
// As above; PLEAT_ERROR_IO when the file cannot be read.
std::shared_ptr<Model> load_model_file(const std::string& path);

// Every float tensor of a model, named as in the loader's messages (e.g.
// "garment_encoder layer 1 weight"), in file order. For tests, tools and
// trainers that map parameters one by one. Views stay valid while the model
// lives and is not changed.
struct TensorView {
  std::string name;
  const float* data = nullptr;
  nn::Index rows = 0;
  nn::Index cols = 0;  // 1-D tensors: rows = 1
  size_t size() const { return static_cast<size_t>(rows) * static_cast<size_t>(cols); }
};
std::vector<TensorView> model_tensors(const Model& model);

}  // namespace pleat::runtime
