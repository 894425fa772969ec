#pragma once
// The ablation of the paper's Table I: the same data, schedule and seed
// trained four times (GAT + FreqDiv, LGAT + FreqDiv, FlexiGAT without FreqDiv,
// FlexiGAT + FreqDiv), every validation metric of the library per run, and
// the table written as Markdown and CSV.
#include <string>
#include <vector>

#include "trainer.h"

namespace pleat::training {

struct AblationRow {
  std::string name;
  EpochResult result;  // the last epoch's, with the kept epoch's number and validation metrics
};

// Runs into <base.output>/<run name>/ (each resumable) and writes
// <base.output>/ablation.md and ablation.csv.
std::vector<AblationRow> run_ablation(const TrainerConfig& base);

}  // namespace pleat::training
