#pragma once
// The trainer: a model initialised for the data's skeleton (or resumed from a
// checkpoint), trained with Adamax and cosine annealing under the progressive
// schedule, validated every epoch with the library's metrics, checkpointed
// so a resumed run continues exactly, logged as CSV (log.csv per epoch,
// terms.csv per loss term), exported as a model file. docs/training.md
// describes the configuration.
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dataset.h"
#include "losses.h"
#include "metrics/metrics.h"
#include "network.h"
#include "optimizer.h"
#include "runtime/model_init.h"
#include "schedule.h"
#include "trainer_config.h"

namespace pleat::training {

// One weighted term of the loss (its schedule name; the weight applied).
struct LossTerm {
  std::string name;
  torch::Tensor value;
};

// A term over an epoch: its frame-weighted mean, and the norm of its gradient
// over every trained parameter on the epoch's first batch (what it pulls with,
// against the others).
struct TermStats {
  double loss = 0.0;
  double gradient_norm = 0.0;
};

struct EpochResult {
  int64_t epoch = 0;
  std::string phase;
  double learning_rate = 0.0;
  double loss = 0.0;              // mean weighted loss over the epoch's batches
  double train_e_verts_cm = 0.0;  // mean vertex distance of the training batches
  std::map<std::string, TermStats> terms;
  MetricsResult validation;  // on the validation sequences (zeros without any)
  double seconds = 0.0;
  double frames_per_second = 0.0;  // training frames (forward + backward)
};

class Trainer {
 public:
  // Loads the data, then resumes from config.output's checkpoint if one
  // exists, else initialises a model for the first training body's skeleton.
  explicit Trainer(TrainerConfig config);

  // Trains up to config.epochs (counting resumed ones), or up to
  // `stop_after` epochs when that is smaller (an interrupted run), checkpointing
  // after each epoch; returns the last epoch's result.
  EpochResult run(int64_t stop_after = 0);
  EpochResult train_epoch();
  MetricsResult validate(const Dataset& data);

  // The kept epoch's weights as a model: with validation data the epoch with
  // the lowest validation E_verts (best_epoch()), else the last. E_verts is
  // the error a user sees; the other metrics are logged, they do not veto.
  std::shared_ptr<runtime::Model> export_model() const;
  int64_t epoch() const { return epoch_; }
  int64_t best_epoch() const { return best_epoch_; }  // 0: none kept (no validation data)
  // The epoch export_model() writes.
  int64_t exported_epoch() const { return best_epoch_ > 0 ? best_epoch_ : epoch_; }
  const MetricsResult& best_validation() const { return best_validation_; }
  const MetricsResult& validation_baseline() const { return validation_lbs_; }
  const MetricsResult& training_baseline() const { return train_lbs_; }
  Network& network() { return network_; }
  const Dataset& training_data() const { return train_; }

 private:
  std::shared_ptr<runtime::Model> starting_model(const Body& body);
  struct Garments;  // losses' per-garment data (geometry, bands)
  std::vector<LossTerm> batch_loss(const TrainingSequence& s, const std::vector<int64_t>& frames,
                                   double* vertex_cm);
  std::map<std::string, double> gradient_norms(const std::vector<LossTerm>& terms);
  void keep_if_best(const EpochResult& r);
  void save_checkpoint() const;
  bool load_checkpoint();
  void log(const EpochResult& r) const;
  void plot() const;

  TrainerConfig config_;
  Dataset train_, validation_;
  std::shared_ptr<runtime::Model> initial_;
  Network network_{nullptr};
  std::unique_ptr<Adamax> optimizer_;
  ScheduleState schedule_;
  std::vector<std::unique_ptr<BoundGarment>> bound_train_, bound_validation_;
  std::map<const Garment*, std::pair<std::unique_ptr<GarmentGeometry>, std::unique_ptr<BandProjector>>>
      garments_;
  std::mt19937_64 rng_;
  int64_t epoch_ = 0;
  MetricsResult last_validation_;
  MetricsResult validation_lbs_, train_lbs_;  // the LBS baseline on each split
  // The kept epoch (best.pt): its number, validation metrics, weights.
  int64_t best_epoch_ = 0;
  MetricsResult best_validation_;
  std::vector<torch::Tensor> best_parameters_;
};

}  // namespace pleat::training
