#include "body/motion_file.h"

#include <cctype>
#include <cmath>
#include <filesystem>

#include "body/bvh.h"
#include "body/rig_import.h"
#include "core/error.h"

namespace pleat {

MotionFile read_motion_file(const std::string& path, double unit_scale, uint32_t clip) {
  if (!(std::isfinite(unit_scale) && unit_scale >= 0.0))
    fail(PLEAT_ERROR_INVALID_ARGUMENT, path + ": unit_scale must be finite and >= 0");
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".bvh") {
    BvhOptions b;
    b.scale = unit_scale;
    BvhClip bvh = read_bvh(path, b);
    return {std::move(bvh.motion), bvh.conversion.scale};
  }
  RigImportOptions r;
  if (unit_scale > 0.0) r.scale = unit_scale;
  ImportedRig rig = import_rig(path, r);
  if (clip >= rig.clips.size())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, path + ": clip " + std::to_string(clip) + " requested, the file has " +
                                           std::to_string(rig.clips.size()) + " animation clip(s)");
  return {std::move(rig.clips[clip].motion), rig.unit_scale};
}

}  // namespace pleat
