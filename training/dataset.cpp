#include "dataset.h"

#include <algorithm>
#include <filesystem>
#include <numeric>

#include "body/body_source.h"
#include "capi/pleat.h"
#include "core/error.h"
#include "core/geometry.h"

namespace pleat::training {
namespace {

torch::Tensor frames_tensor(const std::vector<float>& data, int64_t frames) {
  return torch::from_blob(const_cast<float*>(data.data()),
                          {frames, static_cast<int64_t>(data.size()) / (frames * 3), 3}, torch::kFloat32)
      .clone();
}

}  // namespace

runtime::PoseSequence TrainingSequence::poses() const {
  return {rotations.data(), root_positions.data(), meta.frame_count,
          static_cast<int32_t>(meta.joint_names.size()), meta.frame_rate};
}

Dataset::Dataset(const std::vector<std::string>& dirs) {
  for (const std::string& dir : dirs) {
    SequenceData data = read_sequence(dir);
    TrainingSequence s;
    s.dir = dir;
    s.meta = data.meta;
    // Garment: welded once per name and prepared; the simulated frames follow
    // garment.obj's vertex order, mapped onto the welded vertices.
    auto& garment = garments_[s.meta.garment_name];
    if (!garment) {
      Garment g =
          build_garment(data.garment_rest.vertices, data.garment_rest.triangles, {}, dir + "/garment.obj");
      g.prepared = prepare_garment(g, BandOptions{}, kDefaultGeodesicRadius);
      garment = std::make_shared<const Garment>(std::move(g));
    }
    if (static_cast<int64_t>(garment->source_vertex.size()) != data.garment_rest.vertex_count())
      fail(PLEAT_ERROR_FORMAT, "sequence '" + dir + "': garment '" + s.meta.garment_name + "' has " +
                                   std::to_string(data.garment_rest.vertex_count()) + " vertices here but " +
                                   std::to_string(garment->source_vertex.size()) + " in an earlier sequence");
    s.garment = garment;
    const int64_t frames = s.meta.frame_count, n = garment->rest.vertex_count();
    const torch::Tensor unwelded = frames_tensor(data.garment_frames, frames);
    std::vector<int64_t> representative(static_cast<size_t>(n), -1);
    for (size_t i = 0; i < garment->source_vertex.size(); ++i)
      if (representative[garment->source_vertex[i]] < 0)
        representative[garment->source_vertex[i]] = static_cast<int64_t>(i);
    s.truth = unwelded.index_select(1, torch::tensor(representative, torch::kInt64)).contiguous();

    // Body: the recorded source (relative to the folder) and shape.
    std::string source = s.meta.body_source;
    if (!source.empty() && std::filesystem::path(source).is_relative()) source = dir + "/" + source;
    BodySource body = load_body_source(source, s.meta.body_kind, s.meta.body_rig);
    s.body = s.meta.shape.empty() || !body.reshape ? body.body
                                                   : body.reshape(shape_values(body.body, s.meta.shape));
    if (s.body.skeleton.names != s.meta.joint_names)
      fail(PLEAT_ERROR_FORMAT, "sequence '" + dir +
                                   "': meta.json's motion.joints differ from the joints of body '" + source +
                                   "'");
    s.body_positions = frames_tensor(data.body_frames, frames);
    if (s.body_positions.size(1) != s.body.vertex_count())
      fail(PLEAT_ERROR_FORMAT, "sequence '" + dir + "': body.pc2 has " +
                                   std::to_string(s.body_positions.size(1)) + " vertices, the body " +
                                   std::to_string(s.body.vertex_count()));
    s.body_normals = torch::empty_like(s.body_positions);
    for (int64_t f = 0; f < frames; ++f)
      pleat::vertex_normals(s.body_positions[f].data_ptr<float>(), s.body.vertex_count(),
                            s.body.rest.triangles, s.body_normals[f].data_ptr<float>());
    s.rotations = std::move(data.rotations);
    s.root_positions = std::move(data.root_positions);
    sequences_.push_back(std::move(s));
  }
}

int64_t Dataset::frame_count() const {
  int64_t total = 0;
  for (const TrainingSequence& s : sequences_) total += s.frame_count();
  return total;
}

std::vector<Dataset::Batch> Dataset::epoch(int64_t batch_frames, int64_t sequences_per_batch,
                                           std::mt19937_64& rng) const {
  // Chunks of one sequence's frames, shuffled; a batch is consecutive chunks.
  // With no limit a chunk is one frame, so batches mix sequences freely.
  const int64_t chunk =
      sequences_per_batch > 0 ? (batch_frames + sequences_per_batch - 1) / sequences_per_batch : 1;
  std::vector<std::pair<size_t, std::vector<int64_t>>> chunks;
  for (size_t s = 0; s < sequences_.size(); ++s) {
    std::vector<int64_t> frames(static_cast<size_t>(sequences_[s].frame_count()));
    std::iota(frames.begin(), frames.end(), int64_t{0});
    if (chunk > 1) std::shuffle(frames.begin(), frames.end(), rng);
    for (size_t i = 0; i < frames.size(); i += static_cast<size_t>(chunk))
      chunks.emplace_back(s, std::vector<int64_t>(frames.begin() + static_cast<std::ptrdiff_t>(i),
                                                  frames.begin() + static_cast<std::ptrdiff_t>(std::min(
                                                                       frames.size(), i + size_t(chunk)))));
  }
  std::shuffle(chunks.begin(), chunks.end(), rng);
  std::vector<Batch> batches;
  std::map<size_t, std::vector<int64_t>> by_sequence;
  int64_t in_batch = 0;
  const auto flush = [&] {
    Batch batch;
    for (auto& [sequence, frames] : by_sequence) batch.push_back({sequence, std::move(frames)});
    batches.push_back(std::move(batch));
    by_sequence.clear();
    in_batch = 0;
  };
  for (auto& [sequence, frames] : chunks) {
    if (in_batch + static_cast<int64_t>(frames.size()) > batch_frames) flush();
    in_batch += static_cast<int64_t>(frames.size());
    auto& into = by_sequence[sequence];
    into.insert(into.end(), frames.begin(), frames.end());
  }
  if (in_batch > 0) flush();
  return batches;
}

}  // namespace pleat::training
