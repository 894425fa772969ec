#pragma once
// pleat bench --against-blender: the simulator that made the ground truth,
// timed in the same run on one of the bench's sequences with the datagen
// settings that made it (pleat-datagen --only, into a fresh folder).
#include <string>

#include "bench.h"
#include "dataset.h"

namespace pleat::training {

struct BlenderTiming {
  std::string sequence;          // folder name of the re-simulated sequence
  int threads = 1;               // Blender's (the bench's --threads)
  int64_t frames = 0;            // its output frames
  double seconds = 0.0;          // Blender's wall time for them, lead-in frames included
  double max_deviation_m = 0.0;  // re-simulation against the stored ground truth, largest |Δ|
};

// Runs `datagen_tool` on `datagen_config` for `sequence` into `work`
// (emptied first) with `threads` Blender threads. Blender's cloth result
// depends on its thread count (0.11 m apart after 12 frames of a skirt at 1
// and 2 threads), so the re-simulation matches the stored sequence only at
// the thread count the data set was made with. Throws std::runtime_error
// naming the sequence when the simulation fails or does not produce it.
BlenderTiming time_blender(const std::string& datagen_tool, const std::string& datagen_config,
                           const TrainingSequence& sequence, const std::string& work, int threads);

// The Markdown paragraph comparing it with the report's default setting.
std::string blender_markdown(const BlenderTiming& timing, const BenchReport& report);

}  // namespace pleat::training
