#pragma once
// BVH (Biovision hierarchy) motion reader.
//
// Reads HIERARCHY (one ROOT, JOINT, End Site, OFFSET, CHANNELS with any order
// of X/Y/Zposition and X/Y/Zrotation) and MOTION (Frames, Frame Time, one row
// per frame). Rotation channels compose in the order given, intrinsically:
// "Zrotation Xrotation Yrotation" gives R = Rz * Rx * Ry (angles in degrees).
// The result is a pleat::Motion in pleat conventions (metres, Y up): identity
// rest rotations, rest_translation = OFFSET, root_translation per frame from
// the root's position channels. End Sites are not joints; they are kept in
// BvhClip::end_sites (useful as toe/finger/head tips).
//
// Conversions, each recorded in BvhConversion:
// * units: `scale` metres per file unit, or a guess from the rest skeleton's
//   height snapped to a known unit (m, dm, cm, mm, inch, CMU ASF unit of
//   1/0.45 inch) so that the figure is closest to 1.7 m;
// * up axis: Z-up files (MakeHuman exports) are rotated to Y up;
// * position channels: absolute (BVH convention: the value replaces OFFSET) or
//   relative (MakeHuman: the value is added to OFFSET). The guess is
//   "relative" when non-root joints have position channels whose values are
//   near zero while their OFFSETs are not (MakeHuman's exports), else
//   "absolute"; files with root positions only give no evidence, so force
//   BvhPositions::kRelative for MakeHuman poses that have no others. Position
//   channels of non-root joints are not representable in a Motion and are
//   dropped (their largest deviation from OFFSET is recorded);
// * frame rate = 1 / Frame Time, snapped to a whole number within 1e-4
//   relative (".0083333" is 120 fps).
//
// Errors: PLEAT_ERROR_IO for an unreadable file; PLEAT_ERROR_FORMAT naming the
// file and line for anything malformed (unknown keyword, missing CHANNELS,
// wrong value count on a MOTION line, truncated data, NaN/inf, ...).
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "body/skeleton.h"

namespace pleat {

enum class BvhUpAxis { kAuto, kY, kZ };
enum class BvhPositions { kAuto, kAbsolute, kRelative };

struct BvhOptions {
  double scale = 0.0;  // metres per file unit; 0 = guess from the skeleton height
  BvhUpAxis up_axis = BvhUpAxis::kAuto;
  BvhPositions positions = BvhPositions::kAuto;
  bool snap_frame_rate = true;
};

// What the reader converted, for the record (meta.json, logs).
struct BvhConversion {
  double scale = 1.0;          // metres per file unit used
  bool scale_guessed = false;  // true when guessed from the height
  std::string unit;            // "metre", "centimetre", "inch", "CMU ASF unit", "given", "fit to 1.7 m", ...
  double height_file_units = 0;       // rest skeleton extent along its up axis (joints and end sites)
  double height_m = 0;                // the same in metres
  bool z_up_converted = false;        // the file was Z up and was rotated to Y up
  bool positions_relative = false;    // position channels were added to OFFSET
  int32_t joints_with_positions = 0;  // non-root joints with position channels
  double frame_time = 0;              // as in the header (seconds)
  bool frame_rate_snapped = false;
  int32_t channel_count = 0;              // values per MOTION row
  double dropped_translation_m = 0;       // largest non-root position channel deviation from OFFSET (metres)
  std::string dropped_translation_joint;  // where it occurred ("" if none)
  std::string summary() const;            // one line, human readable
};

struct BvhEndSite {
  int32_t joint = 0;       // the joint the End Site belongs to
  Eigen::Vector3d offset;  // in that joint's frame, metres, Y up
};

struct BvhClip {
  Motion motion;
  std::vector<BvhEndSite> end_sites;
  std::vector<std::string> rotation_orders;  // per joint, e.g. "ZXY" ("" for none)
  BvhConversion conversion;
};

// Reads a .bvh file. `source` in messages is the path.
BvhClip read_bvh(const std::string& path, const BvhOptions& options = {});

// Parses BVH text; `source` names it in error messages.
BvhClip parse_bvh(const std::string& text, const std::string& source, const BvhOptions& options = {});

// The rotation of Euler angles (degrees) applied in the given axis order,
// intrinsic: order "ZXY", degrees (a, b, c) -> Rz(a) * Rx(b) * Ry(c).
Eigen::Quaterniond bvh_euler_rotation(const std::string& order, const Eigen::Vector3d& degrees);

// Global positions of every joint, and of every end site, for frame f.
void bvh_frame_positions(const BvhClip& clip, int64_t frame, Points3d* joints, Points3d* end_sites);

}  // namespace pleat
