#pragma once
// `pleat datagen`: plans the data set, simulates every sequence not yet done
// (in parallel Blender processes), checks each one and writes its folder.
// Resumable: a folder with meta.json from the same job (same hash of every
// input and setting) is kept, a rejected job is remembered; anything
// interrupted is redone.
#include <string>
#include <vector>

#include "config.h"
#include "garment_check.h"

namespace pleat::datagen {

struct GenerateOptions {
  int jobs = 1;             // Blender processes at once
  int blender_threads = 0;  // Blender's -t per process (0: its default)
  std::string only;         // simulate only sequences whose name contains this
  bool dry_run = false;     // print the plan, simulate nothing
  bool progress = true;     // a progress line on stderr
  bool keep_work = false;   // keep each job's Blender folder (the whole simulation, lead-in included)
};

struct SequenceOutcome {
  std::string name, split;
  // "done" (this run), "kept" (earlier run), "rejected", "failed", "planned" (dry run), "skipped" (not
  // matched by --only, or a twin whose original was not accepted)
  std::string status;
  std::string message;
  double seconds = 0;
  CheckReport check;
};

struct GenerateReport {
  std::string output;
  std::vector<SequenceOutcome> sequences;
  int count(const std::string& status) const;
};

// Throws only for problems that stop the whole run (config, assets, output
// folder); a sequence that fails is reported and the others go on. Writes
// <output>/report.tsv (every sequence) and <output>/splits.json (the
// accepted sequences by split).
GenerateReport generate(const Config& config, const GenerateOptions& options);

// FNV-1a 64 of `text`, as 16 hex digits: the job identity kept in meta.json.
std::string job_hash(const std::string& text);

}  // namespace pleat::datagen
