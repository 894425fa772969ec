#pragma once
// The trainer's configuration file (JSON, docs/training.md): which sequences,
// which schedule, where to write, the optimiser's settings and the model to
// build or start from. Reading it needs no libtorch (fuzz_training_config
// runs it under the sanitizers).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "runtime/model_init.h"
#include "schedule.h"

namespace pleat::training {

struct TrainerConfig {
  std::vector<std::string> train, validation, test;  // sequence folders
  // Sequence folder -> its twin (datagen's twins: the noise floor), where the
  // data set has one.
  std::map<std::string, std::string> twins;
  Schedule schedule;
  std::string schedule_source = "inline";
  std::string source = "inline config";  // the config file, for messages
  std::string output;  // folder: checkpoint.pt, checkpoint.json, best.pt, log.csv, model.pleat
  int64_t epochs = 100;
  int64_t batch_frames = 4;
  int64_t sequences_per_batch = 0;  // 0: batches mix frames freely (Dataset::epoch)
  double learning_rate = 3e-3, min_learning_rate = 0.0;
  // Decoupled weight decay of every weight matrix (Adamax::set_weight_decay);
  // biases and FlexiGAT's exponents are not decayed. 0: none.
  double weight_decay = 0.0;
  uint64_t seed = 1;
  bool frequency_division = true;  // false: plain vertex loss (the ablation without FreqDiv)
  runtime::ModelInitOptions model;
  // A model file to start from (fine-tuning: its weights, architecture and
  // settings); empty: a fresh model built from `model`.
  std::string initial_model;
  bool progress = true;  // a progress bar on stderr
  bool plot = true;      // <output>/curves.png from log.csv after each run (matplotlib)
};

// Reads a configuration file (JSON; paths relative to the file).
// Throws PLEAT_ERROR_FORMAT naming the file and key. An empty training list
// is read (evaluate only needs the test split); the Trainer refuses it.
TrainerConfig read_trainer_config(const std::string& path);

}  // namespace pleat::training
