#pragma once
// A motion clip from a file: BVH (by extension), else a rig file's animation
// (body/rig_import: glTF, FBX, ...). Shared by the C API and pleat-datagen's importer.
#include <cstdint>
#include <string>

#include "body/skeleton.h"

namespace pleat {

struct MotionFile {
  Motion motion;            // the file's skeleton, its own frame rate
  double unit_scale = 1.0;  // applied to reach metres
};

// unit_scale 0: the file's own unit (BVH: guessed from the skeleton's size);
// `clip` picks one animation of a file that holds several. Throws the
// readers' errors and PLEAT_ERROR_INVALID_ARGUMENT for a bad scale or a clip
// the file does not have.
MotionFile read_motion_file(const std::string& path, double unit_scale = 0.0, uint32_t clip = 0);

}  // namespace pleat
