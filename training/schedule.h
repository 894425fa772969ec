#pragma once
// The progressive training schedule of the paper (§IV-A) as data: phases,
// each with the loss weights it sets, the parameters it freezes and the
// condition that moves training to the next phase. data/schedules/paper.json
// is the paper's; docs/training.md describes the format.
#include <map>
#include <string>
#include <vector>

namespace pleat::training {

// Loss names: vertex, edge, normal, collision, self_collision, gravity,
// stretch, shear, bending; k_mid and k_high weight the vertex loss's bands.
using LossWeights = std::map<std::string, double>;
const std::vector<std::string>& loss_names();

struct Phase {
  std::string name;
  LossWeights weights;            // set (added or replaced) on entering the phase
  double scale_supervised = 1.0;  // multiplies vertex, edge, curvature and normal on entering
  bool freeze_encoders = false;   // body, garment and motion encoders stop learning
  // Advance when any condition that is set holds at the end of an epoch.
  double e_verts_below_cm = 0.0;     // validation (or training) E_verts
  int64_t plateau_epochs = 0;        // E_verts improved by less than plateau_improvement
  double plateau_improvement = 0.0;  //   (relative) over the last plateau_epochs epochs
  double loss_below = 0.0;           // the epoch's mean total loss
  int64_t epochs = 0;                // epochs spent in this phase
};

struct Schedule {
  std::vector<Phase> phases;
};

// Reads a schedule (JSON). Throws PLEAT_ERROR_FORMAT naming the file, phase
// and key for unknown keys, loss names or values out of range.
Schedule read_schedule(const std::string& path);
Schedule parse_schedule(const std::string& json, const std::string& source);

// Tracks the current phase and its accumulated weights.
class ScheduleState {
 public:
  explicit ScheduleState(Schedule schedule);
  const Phase& phase() const { return schedule_.phases[index_]; }
  size_t phase_index() const { return index_; }
  const LossWeights& weights() const { return weights_; }
  bool encoders_frozen() const { return frozen_; }
  // End of an epoch: records E_verts and the mean loss; moves to the next
  // phase (returns true) when the current one's condition holds.
  bool end_epoch(double e_verts_cm, double mean_loss);
  // For checkpoints: the phase index, epochs in phase and E_verts history.
  std::string save() const;
  void restore(const std::string& text);

 private:
  void enter(size_t index);
  Schedule schedule_;
  size_t index_ = 0;
  LossWeights weights_;
  bool frozen_ = false;
  int64_t epochs_in_phase_ = 0;
  std::vector<double> history_;  // E_verts per epoch of the current phase
};

}  // namespace pleat::training
