#pragma once
// Run time against error (`pleat-train bench`, issue 23): one model on
// sequences with ground truth, evaluated by the runtime under each setting a
// host can choose (stage, top-k, refinement interval), next to the trainer's
// libtorch network on the same weights and plain LBS, all in one run. Each
// row has ms/frame and the Table I metrics; the Pareto front of ms/frame
// against E_verts is marked.
#include <memory>
#include <string>
#include <vector>

#include "dataset.h"
#include "metrics/metrics.h"
#include "runtime/instance.h"
#include "runtime/model.h"

namespace pleat::training {

struct BenchSetting {
  std::string name;
  runtime::Stage stage = runtime::Stage::refinement;
  int32_t top_k = 0;  // 0: the model's default
  runtime::EvaluateDetail detail;
  // In (0, 1): a vertex mask leaves only the garment vertices below this
  // fraction of its rest height to the networks (e.g. 0.5: the skirt of a
  // dress whose bodice is under a jacket); 0: no mask.
  float active_below_height = 0.0f;
};

// The settings a bench measures by default: the three stages, top-k 2, 8
// and every joint, refinement every 2nd, 4th and 8th frame, the
// refinement's high (and mid) band dropped, the body-collision post-pass, a
// vertex mask leaving the lower half.
std::vector<BenchSetting> default_bench_settings();

struct BenchOptions {
  int32_t threads = 2;       // the runtime's and libtorch's
  int32_t repeats = 5;       // timed rounds over every row; each row keeps its median
  int32_t batch_frames = 8;  // frames per evaluate call
  bool libtorch = true;      // time the trainer's network too
};

struct BenchRow {
  std::string engine;  // "pleat", "libtorch", "LBS"
  std::string setting;
  double ms_per_frame = 0.0;
  MetricsResult metrics;
  bool pareto = false;  // no other row is both faster and more accurate (E_verts)
};

struct BenchReport {
  std::vector<BenchRow> rows;
  std::string machine;  // CPU name, load average, kernel path, threads
  int64_t frames = 0;
  int64_t vertices = 0;  // per frame, summed over sequences' garments / sequences
};

// Throws std::invalid_argument when the model cannot drive a sequence's body
// (the message names the sequence and the joint).
BenchReport run_bench(const Dataset& data, const std::shared_ptr<const runtime::Model>& model,
                      const std::vector<BenchSetting>& settings, const BenchOptions& options);

std::string bench_markdown(const BenchReport& report);
std::string bench_csv(const BenchReport& report);

}  // namespace pleat::training
