#include "bench.h"

#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "core/error.h"
#include "evaluation.h"
#include "network.h"
#include "nn/kernel_path.h"

namespace pleat::training {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

std::string machine_line(int32_t threads) {
  std::string cpu = "unknown CPU", load = "?";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);)
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  std::ifstream loadavg("/proc/loadavg");
  std::getline(loadavg, load);
  return cpu + "; load average " + load.substr(0, load.find(' ', load.find(' ', load.find(' ') + 1) + 1)) +
         "; kernel path " + nn::kernel_path_name(nn::kernel_path()) + "; threads: " + std::to_string(threads);
}

// One row of the table: bound once (not timed), then timed passes, each
// predicting every frame of every sequence into `predicted`.
class Contender {
 public:
  Contender(std::string engine, std::string setting)
      : engine_(std::move(engine)), setting_(std::move(setting)) {}
  virtual ~Contender() = default;
  virtual void pass(const Dataset& data) = 0;

  BenchRow row(const Dataset& data, double seconds_per_pass) const {
    BenchRow r{engine_, setting_, 1e3 * seconds_per_pass / double(data.frame_count()), {}, false};
    for (size_t i = 0; i < predicted.size(); ++i)
      accumulate(&r.metrics, sequence_metrics(data.sequences()[i], predicted[i].data()));
    return r;
  }

 protected:
  std::vector<std::vector<float>> predicted;  // per sequence: frames x N x 3

 private:
  std::string engine_, setting_;
};

// The runtime under one host setting, batches of batch_frames frames.
class RuntimeContender : public Contender {
 public:
  RuntimeContender(const Dataset& data, const std::shared_ptr<const runtime::Model>& model,
                   const BenchSetting& setting, const BenchOptions& options)
      : Contender("pleat", setting.name), setting_(setting), batch_(options.batch_frames) {
    runtime::InstanceOptions io;
    io.threads = options.threads;
    io.top_k = setting.top_k;
    io.max_batch = options.batch_frames;
    for (const TrainingSequence& s : data.sequences()) {
      try {
        instances_.push_back(std::make_unique<runtime::Instance>(model, s.garment, s.body, io));
      } catch (const Error& e) {
        if (e.status() != PLEAT_ERROR_INVALID_ARGUMENT) throw;
        throw std::invalid_argument("model '" + model->source + "' cannot drive sequence '" + s.dir +
                                    "': " + e.what());
      }
      predicted.emplace_back(static_cast<size_t>(s.frame_count() * instances_.back()->vertex_count() * 3));
      if (setting.active_below_height > 0.0f)
        instances_.back()->set_vertex_mask(lower_part(s, setting).data());
    }
  }

  void pass(const Dataset& data) override {
    for (size_t i = 0; i < instances_.size(); ++i) {
      const TrainingSequence& s = data.sequences()[i];
      const runtime::PoseSequence poses = s.poses();
      const int64_t n = instances_[i]->vertex_count();
      for (int64_t f = 0; f < s.frame_count(); f += batch_) {
        runtime::EvaluateOutputs out;
        out.positions = {predicted[i].data() + f * n * 3, static_cast<size_t>(n * 3)};
        instances_[i]->evaluate(poses, f, std::min<int64_t>(batch_, s.frame_count() - f), setting_.stage, out,
                                setting_.detail);
      }
    }
  }

 private:
  // The vertices below setting.active_below_height of the rest garment's height.
  static std::vector<uint8_t> lower_part(const TrainingSequence& s, const BenchSetting& setting) {
    const auto y = s.garment->rest.vertices.col(1);
    const double cut = y.minCoeff() + setting.active_below_height * (y.maxCoeff() - y.minCoeff());
    std::vector<uint8_t> mask(static_cast<size_t>(y.size()));
    for (Eigen::Index v = 0; v < y.size(); ++v) mask[static_cast<size_t>(v)] = y[v] < cut;
    return mask;
  }

  BenchSetting setting_;
  int64_t batch_;
  std::vector<std::unique_ptr<runtime::Instance>> instances_;
};

// The trainer's network on the same weights, forward only, batches of
// batch_frames frames. Its forward re-encodes the garment and the body on
// every call (the trainer's weights change between calls); that is part of
// what it costs here.
class LibtorchContender : public Contender {
 public:
  LibtorchContender(const Dataset& data, const runtime::Model& model, const BenchOptions& options)
      : Contender("libtorch", "full stage, exact softmax (trainer's forward)"),
        network_(model),
        batch_(options.batch_frames) {
    network_->eval();
    for (const TrainingSequence& s : data.sequences()) {
      bound_.push_back(std::make_unique<BoundGarment>(model, s.garment, s.body));
      predicted.emplace_back(static_cast<size_t>(s.frame_count() * bound_.back()->vertex_count() * 3));
    }
  }

  void pass(const Dataset& data) override {
    torch::NoGradGuard no_grad;
    for (size_t i = 0; i < bound_.size(); ++i) {
      const TrainingSequence& s = data.sequences()[i];
      const int64_t n = bound_[i]->vertex_count();
      for (int64_t f = 0; f < s.frame_count(); f += batch_) {
        std::vector<int64_t> frames;
        for (int64_t k = f; k < std::min<int64_t>(s.frame_count(), f + batch_); ++k) frames.push_back(k);
        const torch::Tensor x = network_->forward(*bound_[i], s.poses(), frames, runtime::Stage::refinement)
                                    .positions.contiguous();
        std::copy(x.data_ptr<float>(), x.data_ptr<float>() + x.numel(), predicted[i].data() + f * n * 3);
      }
    }
  }

 private:
  Network network_;
  int64_t batch_;
  std::vector<std::unique_ptr<BoundGarment>> bound_;
};

class LbsContender : public Contender {
 public:
  explicit LbsContender(const Dataset& data)
      : Contender("LBS", "nearest body weights, reference loop (1 thread, double)") {
    for (const TrainingSequence& s : data.sequences()) {
      lbs_.push_back(std::make_unique<NearestWeightsLbs>(s));
      predicted.emplace_back(static_cast<size_t>(s.frame_count() * s.garment->rest.vertex_count() * 3));
    }
  }

  void pass(const Dataset& data) override {
    for (size_t i = 0; i < lbs_.size(); ++i)
      lbs_[i]->frames(0, data.sequences()[i].frame_count(), predicted[i].data());
  }

 private:
  std::vector<std::unique_ptr<NearestWeightsLbs>> lbs_;
};

void mark_pareto(std::vector<BenchRow>& rows) {
  for (BenchRow& r : rows) {
    r.pareto = true;
    for (const BenchRow& o : rows) {
      const bool no_worse = o.ms_per_frame <= r.ms_per_frame && o.metrics.e_verts_cm <= r.metrics.e_verts_cm;
      const bool better = o.ms_per_frame < r.ms_per_frame || o.metrics.e_verts_cm < r.metrics.e_verts_cm;
      if (&o != &r && no_worse && better) r.pareto = false;
    }
  }
}

}  // namespace

std::vector<BenchSetting> default_bench_settings() {
  using runtime::Stage;
  constexpr int32_t kEveryJoint = 1 << 20;  // clamped to the skeleton: the exact softmax
  const runtime::EvaluateDetail every{1, {}};
  return {{"full (default)", Stage::refinement, 0, every},
          {"full, refinement every 2nd frame", Stage::refinement, 0, {2, {}}},
          {"full, refinement every 4th frame", Stage::refinement, 0, {4, {}}},
          {"full, refinement every 8th frame", Stage::refinement, 0, {8, {}}},
          {"full, refinement's high band dropped", Stage::refinement, 0, {1, {0.0f, 0.0f, 1.0f}}},
          {"full, refinement's mid and high bands dropped", Stage::refinement, 0, {1, {0.0f, 1.0f, 1.0f}}},
          {"full, top-2 skinning", Stage::refinement, 2, every},
          {"full, top-8 skinning", Stage::refinement, 8, every},
          {"full, exact skinning (every joint)", Stage::refinement, kEveryJoint, every},
          {"blend-shape stage", Stage::blend_shapes, 0, every},
          {"skinning stage", Stage::skinning, 0, every},
          {"full + body-collision post-pass (2 mm)", Stage::refinement, 0, {1, {}, 0.002f}},
          {"full, vertex mask: lower half of the garment active", Stage::refinement, 0, every, 0.5f}};
}

BenchReport run_bench(const Dataset& data, const std::shared_ptr<const runtime::Model>& model,
                      const std::vector<BenchSetting>& settings, const BenchOptions& options) {
  if (data.sequences().empty()) throw std::invalid_argument("bench needs at least one sequence");
  if (options.threads < 1 || options.repeats < 1 || options.batch_frames < 1)
    throw std::invalid_argument("bench threads, repeats and batch frames must be at least 1");
  BenchReport report;
  report.machine = machine_line(options.threads);
  report.frames = data.frame_count();
  for (const TrainingSequence& s : data.sequences()) report.vertices += s.garment->rest.vertex_count();
  report.vertices /= static_cast<int64_t>(data.sequences().size());
  const int torch_threads = torch::get_num_threads();
  torch::set_num_threads(options.threads);
  std::vector<std::unique_ptr<Contender>> contenders;
  for (const BenchSetting& setting : settings)
    contenders.push_back(std::make_unique<RuntimeContender>(data, model, setting, options));
  if (options.libtorch) contenders.push_back(std::make_unique<LibtorchContender>(data, *model, options));
  contenders.push_back(std::make_unique<LbsContender>(data));
  // A warm-up pass each, then rounds that time every contender once: on a
  // shared, noisy machine a slow spell then hits every row alike, and each
  // row keeps its median over the rounds.
  std::vector<std::vector<double>> seconds(contenders.size());
  for (int32_t round = 0; round <= options.repeats; ++round) {
    std::fprintf(stderr, "bench: %s %d of %d\n", round == 0 ? "warm-up" : "round", round == 0 ? 1 : round,
                 round == 0 ? 1 : options.repeats);
    for (size_t c = 0; c < contenders.size(); ++c) {
      const auto start = Clock::now();
      contenders[c]->pass(data);
      if (round > 0) seconds[c].push_back(seconds_since(start));
    }
  }
  torch::set_num_threads(torch_threads);
  for (size_t c = 0; c < contenders.size(); ++c)
    report.rows.push_back(contenders[c]->row(data, median(seconds[c])));
  mark_pareto(report.rows);
  return report;
}

std::string bench_markdown(const BenchReport& report) {
  std::string out = "Machine: " + report.machine + ". " + std::to_string(report.frames) + " frames, " +
                    std::to_string(report.vertices) + " garment vertices per frame.\n\n" +
                    "| engine | setting | ms/frame | fps | E_verts cm | E_mid cm | E_high cm | E_curv | body "
                    "penetration % | "
                    "Pareto |\n"
                    "|---|---|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const BenchRow& r : report.rows) {
    char line[512];
    std::snprintf(line, sizeof line, "| %s | %s | %.3f | %.0f | %.3f | %.3f | %.3f | %.1f | %.2f | %s |\n",
                  r.engine.c_str(), r.setting.c_str(), r.ms_per_frame, 1e3 / r.ms_per_frame,
                  r.metrics.e_verts_cm, r.metrics.e_mid_cm, r.metrics.e_high_cm, r.metrics.e_curv,
                  r.metrics.body_penetration_percent, r.pareto ? "yes" : "");
    out += line;
  }
  return out;
}

std::string bench_csv(const BenchReport& report) {
  std::string out =
      "engine,setting,ms_per_frame,e_verts_cm,e_mid_cm,e_high_cm,e_curv,body_penetration_percent,pareto\n";
  for (const BenchRow& r : report.rows) {
    char line[512];
    std::snprintf(line, sizeof line, "%s,\"%s\",%.6f,%.6f,%.6f,%.6f,%.6f,%.4f,%d\n", r.engine.c_str(),
                  r.setting.c_str(), r.ms_per_frame, r.metrics.e_verts_cm, r.metrics.e_mid_cm,
                  r.metrics.e_high_cm, r.metrics.e_curv, r.metrics.body_penetration_percent,
                  r.pareto ? 1 : 0);
    out += line;
  }
  return out;
}

}  // namespace pleat::training
