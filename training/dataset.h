#pragma once
// Training data: sequence folders (io/sequence.h, docs/data.md) loaded with
// their garment (welded, prepared: bands and geodesic neighbourhoods, once per
// garment name), their body (the recorded source and shape), the poses, and
// the simulated garment and posed body as tensors; and mini-batches of
// frames drawn across several sequences.
#include <torch/torch.h>

#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "body/body.h"
#include "garment/garment.h"
#include "io/sequence.h"
#include "runtime/instance.h"

namespace pleat::training {

struct TrainingSequence {
  std::string dir;
  SequenceMeta meta;
  std::shared_ptr<const Garment> garment;  // welded and prepared
  Body body;
  std::vector<float> rotations, root_positions;  // the body's joint order
  torch::Tensor truth;                           // frames x N x 3: the simulated garment, welded vertex order
  torch::Tensor body_positions;                  // frames x body vertices x 3
  torch::Tensor body_normals;                    // frames x body vertices x 3 (area-weighted, unit)
  runtime::PoseSequence poses() const;
  int64_t frame_count() const { return meta.frame_count; }
};

class Dataset {
 public:
  // Loads every folder (relative body paths resolve against the folder).
  // Throws the readers' errors naming the folder; PLEAT_ERROR_FORMAT when the
  // recorded joints differ from the body's.
  explicit Dataset(const std::vector<std::string>& dirs);
  const std::vector<TrainingSequence>& sequences() const { return sequences_; }
  int64_t frame_count() const;

  // One epoch's mini-batches: every frame of every sequence once, shuffled
  // with `rng` and cut into batches of at most `batch_frames`. Within a batch
  // the frames are grouped by sequence (one network pass, and one body
  // encoding, per group). sequences_per_batch 0: frames are shuffled together,
  // so a batch mixes garments, bodies and motions freely; k > 0: a batch holds
  // ceil(batch_frames / k)-frame chunks of at most k sequences, which costs k
  // body encodings per batch instead of up to batch_frames.
  struct Part {
    size_t sequence;
    std::vector<int64_t> frames;
  };
  using Batch = std::vector<Part>;
  std::vector<Batch> epoch(int64_t batch_frames, int64_t sequences_per_batch, std::mt19937_64& rng) const;

 private:
  std::vector<TrainingSequence> sequences_;
  std::map<std::string, std::shared_ptr<const Garment>> garments_;  // by garment name
};

}  // namespace pleat::training
