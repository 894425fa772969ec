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

// Runs into <base.output>/<run name>/ (each resumable, each leaving its
// kept epoch in model.pleat) and writes <base.output>/ablation.md and
// ablation.csv. With `only` (a run name) it
// trains that run alone and writes no table: one process per core, and a
// last call without `only` finds every run done and writes the table.
// Throws INVALID_ARGUMENT on an unknown name.
std::vector<AblationRow> run_ablation(const TrainerConfig& base, const std::string& only = "");

}  // namespace pleat::training
