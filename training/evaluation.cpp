#include "evaluation.h"

#include <algorithm>

#include "body/skinning.h"
#include "capi/pleat.h"
#include "core/error.h"
#include "metrics/body_penetration.h"
#include "spectral/band_split.h"

namespace pleat::training {

MetricsResult sequence_metrics(const TrainingSequence& s, const float* predicted) {
  const int64_t n = s.garment->rest.vertex_count();
  const size_t frame = static_cast<size_t>(n) * 3;
  const torch::Tensor truth = s.truth.contiguous();
  const BandBasis<float>& basis = s.garment->prepared->bands;
  const BandSplitFn split = [&](const float* in, size_t frames, float* low, float* mid, float* high) {
    split_bands(basis, in, frames, frame, low, frame, mid, frame, high, frame);
  };
  MetricsOptions options;
  options.flags = PLEAT_METRIC_VERTEX | PLEAT_METRIC_NORMALS | PLEAT_METRIC_EDGES | PLEAT_METRIC_CURVATURE |
                  PLEAT_METRIC_BANDS | PLEAT_METRIC_SELF_COLLISION;
  MetricsResult m =
      compute_metrics(s.garment->rest.triangles, static_cast<int32_t>(n), predicted, 0,
                      truth.data_ptr<float>(), 0, static_cast<size_t>(s.frame_count()), options, &split);
  const torch::Tensor body = s.body_positions.contiguous(), normals = s.body_normals.contiguous();
  m.body_penetration_percent = body_penetration_percent(
      predicted, n, body.data_ptr<float>(), normals.data_ptr<float>(), body.size(1), s.frame_count());
  return m;
}

void accumulate(MetricsResult* total, const MetricsResult& m) {
  const double before = double(total->frame_count), w = double(m.frame_count), after = before + w;
  if (after <= 0) return;
  const auto mix = [&](double& a, double b) { a = (a * before + b * w) / after; };
  mix(total->e_verts_cm, m.e_verts_cm);
  mix(total->e_vnorm_deg, m.e_vnorm_deg);
  mix(total->e_fnorm_deg, m.e_fnorm_deg);
  mix(total->e_edge_percent, m.e_edge_percent);
  mix(total->e_curv, m.e_curv);
  mix(total->e_low_cm, m.e_low_cm);
  mix(total->e_mid_cm, m.e_mid_cm);
  mix(total->e_high_cm, m.e_high_cm);
  mix(total->self_collision_percent, m.self_collision_percent);
  mix(total->body_penetration_percent, m.body_penetration_percent);
  total->frame_count += m.frame_count;
  total->computed = m.computed;
}

const std::vector<TableMetric>& table_metrics() {
  static const std::vector<TableMetric> metrics = {
      {"e_verts_cm", &MetricsResult::e_verts_cm},
      {"e_vnorm_deg", &MetricsResult::e_vnorm_deg},
      {"e_fnorm_deg", &MetricsResult::e_fnorm_deg},
      {"e_edge_percent", &MetricsResult::e_edge_percent},
      {"e_curv", &MetricsResult::e_curv},
      {"e_low_cm", &MetricsResult::e_low_cm},
      {"e_mid_cm", &MetricsResult::e_mid_cm},
      {"e_high_cm", &MetricsResult::e_high_cm},
      {"self_collision_percent", &MetricsResult::self_collision_percent}};
  return metrics;
}

double worst_ratio(const MetricsResult& model, const MetricsResult& baseline) {
  double worst = 0.0;
  for (const TableMetric& m : table_metrics())
    if (baseline.*m.field > 0.0) worst = std::max(worst, model.*m.field / (baseline.*m.field));
  return worst;
}

NearestWeightsLbs::NearestWeightsLbs(const TrainingSequence& s)
    : sequence_(s),
      weights_(nearest_vertex_weights(s.body, s.garment->rest.vertices)),
      rest_global_(rest_transforms(s.body.skeleton)),
      pose_(static_cast<size_t>(s.body.joint_count())) {}

void NearestWeightsLbs::frames(int64_t first, int64_t count, float* out) {
  const TrainingSequence& s = sequence_;
  const Points3d& rest = s.garment->rest.vertices;
  const int32_t joints = s.body.joint_count();
  for (int64_t f = first; f < first + count; ++f) {
    for (int32_t j = 0; j < joints; ++j) {
      const float* q = s.rotations.data() + (f * joints + j) * 4;
      pose_[static_cast<size_t>(j)] = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized();
    }
    const float* root = s.root_positions.data() + f * 3;
    forward_kinematics(s.body.skeleton, pose_.data(), Eigen::Vector3d(root[0], root[1], root[2]), &global_);
    skinning_matrices(global_, rest_global_, &matrices_);
    posed_.resize(rest.rows(), 3);
    linear_blend_skinning(rest, weights_, matrices_, &posed_);
    for (Eigen::Index i = 0; i < posed_.size(); ++i) *out++ = static_cast<float>(posed_.data()[i]);
  }
}

MetricsResult frame_weighted(const std::vector<MetricsResult>& per_sequence) {
  MetricsResult total;
  for (const MetricsResult& m : per_sequence) accumulate(&total, m);
  return total;
}

MetricsResult frame_weighted(const std::vector<MetricsResult>& per_sequence,
                             const std::vector<size_t>& indices) {
  MetricsResult total;
  for (size_t i : indices) accumulate(&total, per_sequence.at(i));
  return total;
}

std::vector<float> lbs_frames(const TrainingSequence& s) {
  std::vector<float> out(static_cast<size_t>(s.frame_count() * s.garment->rest.vertex_count() * 3));
  NearestWeightsLbs(s).frames(0, s.frame_count(), out.data());
  return out;
}

std::vector<MetricsResult> lbs_per_sequence(const Dataset& data) {
  std::vector<MetricsResult> out;
  for (const TrainingSequence& s : data.sequences()) out.push_back(sequence_metrics(s, lbs_frames(s).data()));
  return out;
}

MetricsResult lbs_baseline(const Dataset& data) {
  return frame_weighted(lbs_per_sequence(data));
}

MetricsResult twin_metrics(const TrainingSequence& s, const TrainingSequence& twin, size_t index) {
  if (twin.frame_count() != s.frame_count() || twin.truth.size(1) != s.truth.size(1))
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         "twin of sequence " + std::to_string(index) + " has " + std::to_string(twin.frame_count()) +
             " frames of " + std::to_string(twin.truth.size(1)) + " vertices, the sequence " +
             std::to_string(s.frame_count()) + " of " + std::to_string(s.truth.size(1)));
  const torch::Tensor truth = twin.truth.contiguous();
  return sequence_metrics(s, truth.data_ptr<float>());
}

MetricsResult twin_difference(const Dataset& data, const Dataset& twins) {
  if (twins.sequences().size() != data.sequences().size())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "twin_difference: " + std::to_string(twins.sequences().size()) +
                                           " twins for " + std::to_string(data.sequences().size()) +
                                           " sequences");
  MetricsResult total;
  for (size_t i = 0; i < data.sequences().size(); ++i)
    accumulate(&total, twin_metrics(data.sequences()[i], twins.sequences()[i], i));
  return total;
}

std::vector<float> model_frames(const TrainingSequence& s, const std::shared_ptr<const runtime::Model>& model,
                                runtime::Stage stage, const runtime::InstanceOptions& options) {
  runtime::Instance instance(model, s.garment, s.body, options);
  const int64_t n = instance.vertex_count(), batch = instance.max_batch();
  std::vector<float> predicted(static_cast<size_t>(s.frame_count() * n * 3));
  const runtime::PoseSequence poses = s.poses();
  for (int64_t f = 0; f < s.frame_count(); f += batch) {
    runtime::EvaluateOutputs out;
    out.positions = {predicted.data() + f * n * 3, static_cast<size_t>(n * 3)};
    instance.evaluate(poses, f, std::min(batch, s.frame_count() - f), stage, out);
  }
  return predicted;
}

std::vector<MetricsResult> model_per_sequence(const Dataset& data,
                                              const std::shared_ptr<const runtime::Model>& model,
                                              runtime::Stage stage, const runtime::InstanceOptions& options) {
  std::vector<MetricsResult> out;
  for (const TrainingSequence& s : data.sequences())
    out.push_back(sequence_metrics(s, model_frames(s, model, stage, options).data()));
  return out;
}

MetricsResult model_metrics(const Dataset& data, const std::shared_ptr<const runtime::Model>& model,
                            runtime::Stage stage, const runtime::InstanceOptions& options) {
  return frame_weighted(model_per_sequence(data, model, stage, options));
}

}  // namespace pleat::training
