#pragma once
// Metrics of predicted frames against a sequence's simulation (the library's
// metrics, frequency bands of the sequence's prepared garment), their
// frame-weighted mean over several sequences, and the plain LBS baseline of
// the paper's comparison.
#include <vector>

#include "body/skinning.h"
#include "dataset.h"
#include "metrics/metrics.h"

namespace pleat::training {

// predicted: frame_count x N x 3 floats (welded vertex order).
MetricsResult sequence_metrics(const TrainingSequence& s, const float* predicted);

// total <- frame-weighted mean of total and m.
void accumulate(MetricsResult* total, const MetricsResult& m);

// The frame-weighted mean of per-sequence results (of those at `indices`,
// in that order, when given): what the data-set functions below return, so a
// report can score each sequence once and aggregate splits and clips from it.
MetricsResult frame_weighted(const std::vector<MetricsResult>& per_sequence);
MetricsResult frame_weighted(const std::vector<MetricsResult>& per_sequence,
                             const std::vector<size_t>& indices);

// Every garment vertex skinned with the skin weights of its nearest rest body
// vertex (no network): the "LBS" row of the comparison tables. Binding (the
// nearest-vertex search) happens at construction, so frames() is what a
// renderer's LBS would cost per frame.
class NearestWeightsLbs {
 public:
  explicit NearestWeightsLbs(const TrainingSequence& s);
  // Frames [first, first + count) of the sequence's poses: count x N x 3 floats.
  void frames(int64_t first, int64_t count, float* out);

 private:
  const TrainingSequence& sequence_;
  SkinWeights weights_;
  Transforms rest_global_, global_;
  Quaternions pose_;
  SkinMatrices matrices_;
  Points3d posed_;
};
// A whole sequence skinned so: frame_count x N x 3 floats.
std::vector<float> lbs_frames(const TrainingSequence& s);
MetricsResult lbs_baseline(const Dataset& data);
std::vector<MetricsResult> lbs_per_sequence(const Dataset& data);

// The noise floor: each sequence's simulation scored against its twin's
// (datagen twins: the same job with a slightly heavier cloth and a longer
// lead-in), frame-weighted. twins[i] is the twin of data.sequences()[i].
MetricsResult twin_difference(const Dataset& data, const Dataset& twins);
// One sequence against its twin (throws INVALID_ARGUMENT naming `index` when
// their frames or vertices differ).
MetricsResult twin_metrics(const TrainingSequence& s, const TrainingSequence& twin, size_t index);

// Table I's metrics: their names in model files and checkpoints, their fields.
struct TableMetric {
  const char* name;
  double MetricsResult::*field;
};
const std::vector<TableMetric>& table_metrics();

// The largest of model's Table I metrics as a fraction of the baseline's
// (1.5: one metric is 50 % above LBS; below 1: every metric beats it). A
// metric the baseline has at zero is left out, since nothing can beat it.
// The trainer prints it after each epoch; it does not choose the kept epoch.
double worst_ratio(const MetricsResult& model, const MetricsResult& baseline);

// The model run by the runtime (runtime/instance.h, up to `stage`, as a host
// would run it: by default with top-4 skinning) on every sequence,
// frame-weighted over the data set.
// One sequence run by the runtime: frame_count x N x 3 floats.
std::vector<float> model_frames(const TrainingSequence& s, const std::shared_ptr<const runtime::Model>& model,
                                runtime::Stage stage = runtime::Stage::refinement,
                                const runtime::InstanceOptions& options = {});

MetricsResult model_metrics(const Dataset& data, const std::shared_ptr<const runtime::Model>& model,
                            runtime::Stage stage = runtime::Stage::refinement,
                            const runtime::InstanceOptions& options = {});
std::vector<MetricsResult> model_per_sequence(const Dataset& data,
                                              const std::shared_ptr<const runtime::Model>& model,
                                              runtime::Stage stage = runtime::Stage::refinement,
                                              const runtime::InstanceOptions& options = {});

}  // namespace pleat::training
