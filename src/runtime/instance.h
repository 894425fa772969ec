#pragma once
// Instance = bind(model, garment, body): every pose-independent result is
// computed here once (body code, garment encoder output, rest features, the
// body's skeleton mapped onto the model's joints); evaluate() then does only
// per-frame work in preallocated workspaces. One thread at a time per
// instance; instances share the model and garment read-only.
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "body/body.h"
#include "garment/garment.h"
#include "runtime/model.h"

namespace pleat::runtime {

enum class Stage : int32_t { skinning = 1, blend_shapes = 2, refinement = 3 };

struct InstanceOptions {
  int32_t threads = 1;    // own worker pool when > 1
  int32_t top_k = 0;      // joints per vertex in LBS; 0 = the model's default; >= S = exact
  int32_t max_batch = 8;  // frames evaluated together (workspaces are sized for this)
};

// Poses in the body's joint order, as the C API takes them:
// frame_count * joint_count unit quaternions (x, y, z, w) relative to the
// joint's rest orientation, and frame_count root positions (xyz, metres).
// Frames before the evaluated range serve as history (motion window,
// velocities); frames before 0 repeat frame 0.
struct PoseSequence {
  const float* rotations = nullptr;
  const float* root_positions = nullptr;
  int64_t frame_count = 0;
  int32_t joint_count = 0;
  double frame_rate = 30.0;
};

// Per-frame outputs: frame f of a buffer starts at data + f * stride (floats);
// a null data pointer skips that output.
struct OutputBuffer {
  float* data = nullptr;
  size_t stride = 0;
};
struct EvaluateOutputs {
  OutputBuffer positions;         // N x 3
  OutputBuffer normals;           // N x 3 (area-weighted vertex normals of the positions)
  OutputBuffer skinning_weights;  // N x S dense, zero outside each vertex's top k
  OutputBuffer low, mid, high;    // band split of the positions (prepared garment only)
};

// What a host may skip or add per call (docs/runtime.md): the refinement's
// level of detail, and the body-collision post-pass.
struct EvaluateDetail {
  // k >= 1: the refinement runs on frames t with t % k == 0 and its offsets,
  // in the heading frame, are held over the skinned positions of the k - 1
  // frames after.
  int32_t interval = 1;
  // Fraction of the offsets' low, mid and high band removed, each in [0, 1]
  // (needs a prepared garment when any is above 0).
  float band_attenuation[3] = {0.0f, 0.0f, 0.0f};
  // > 0: after the stage, garment vertices inside the body or closer to it
  // than this many metres move out along the body normal
  // (runtime/body_collision.h); 0: off.
  float body_collision = 0.0f;
};

class Instance {
 public:
  // Throws pleat::Error: INVALID_ARGUMENT when the body cannot drive the model
  // (joint names or parents differ; message names the joint), shape entries
  // missing, bad options; NOT_PREPARED never (bands are only needed when the
  // band outputs are asked for).
  Instance(std::shared_ptr<const Model> model, std::shared_ptr<const Garment> garment, const Body& body,
           const InstanceOptions& options);
  ~Instance();
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  // Evaluates frames [first, first + count) of `poses` up to `stage` into the
  // requested outputs. Allocates nothing. Throws INVALID_ARGUMENT (joint count,
  // frame range, frame rate != model's, non-finite or non-unit rotation: frame
  // and joint named), NOT_PREPARED (band outputs on an unprepared garment),
  // NUMERICAL (a non-finite output; nothing is written for that batch).
  void evaluate(const PoseSequence& poses, int64_t first, int64_t count, Stage stage,
                const EvaluateOutputs& outputs, const EvaluateDetail& detail = {});

  // Restricts the blend shapes and the refinement to the vertices whose
  // entry of `mask` (vertex_count() bytes) is nonzero; the others keep the
  // skinning stage's positions (runtime/vertex_mask.h; docs/runtime.md).
  // Null, or every vertex active, clears it. Allocates: call it when the
  // view changes, not per frame.
  void set_vertex_mask(const uint8_t* mask);
  int32_t active_vertex_count() const;  // vertex_count() without a mask

  int32_t vertex_count() const;
  int32_t joint_count() const;
  int32_t top_k() const;
  int32_t max_batch() const;
  const Model& model() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace pleat::runtime
