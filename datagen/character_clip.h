#pragma once
// A character and the clip that drove a simulation, as import-sequences and
// preview read them from the user's files.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "body/body.h"

namespace pleat::datagen {

struct CharacterClip {
  Body body;    // at the given shape
  Motion clip;  // resampled to the frame rate, retargeted onto body
};

// body: a MakeHuman assets folder, an SMPL-layout .npz or a rigged mesh; rig:
// "cmu_mb" or "default" (MakeHuman); shape: named entries; map: a joint map
// file or empty. Throws the loaders' errors (naming file and field).
// "default" -> PLEAT_RIG_MAKEHUMAN_DEFAULT, anything else -> PLEAT_RIG_CMU_MB
// (the configs check the name).
uint32_t makehuman_rig(const std::string& rig);

CharacterClip load_character_clip(const std::string& body, const std::string& rig,
                                  const std::vector<std::pair<std::string, double>>& shape,
                                  const std::string& motion, const std::string& map, double frame_rate);

}  // namespace pleat::datagen
