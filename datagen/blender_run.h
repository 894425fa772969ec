#pragma once
// One simulation in Blender: writes the job folder (rest collider and garment
// OBJ, collider and skinned garment PC2, job.json, the script), runs Blender headless
// on it and reads the simulated garment back.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config.h"
#include "sequence_inputs.h"

namespace pleat::datagen {

// The Blender side (datagen/simulate_cloth.py, compiled in).
extern const char* const kSimulateClothScript;

// Every simulator setting of a job, as recorded in meta.json.
nlohmann::json simulator_settings(const Config& config, const GarmentSpec& garment);

struct BlenderResult {
  std::vector<float> garment_frames;  // every frame (lead-in included) x garment vertices x 3
  std::string blender_version;
  double seconds = 0;               // Blender's time in the simulation loop
  double collider_cache_error = 0;  // evaluated collider vs collider.pc2, m (sanity of the frame mapping)
};

using FrameProgress = std::function<void(int64_t done, int64_t total)>;

// threads: Blender's -t (0: its default). Throws PLEAT_ERROR_IO when Blender
// cannot be started or fails (the message quotes the end of work_dir/blender.log)
// and PLEAT_ERROR_FORMAT when its output does not match the job.
BlenderResult run_blender(const Config& config, const GarmentSpec& garment, const SequenceInputs& inputs,
                          const std::string& work_dir, int threads, const FrameProgress& progress);

}  // namespace pleat::datagen
