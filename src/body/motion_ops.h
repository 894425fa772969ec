#pragma once
// Operations on motions: validation, resampling, cutting, retargeting onto
// another skeleton (by joint names or a mapping file) and left/right mirroring.
#include <string>
#include <utility>
#include <vector>

#include "body/skeleton.h"

namespace pleat {

// Throws PLEAT_ERROR_INVALID_ARGUMENT naming `source`, the joint and the frame:
// invalid skeleton, frame rate not finite > 0, array sizes, non-finite or
// non-unit (|norm - 1| > 1e-6) rotation, non-finite root translation.
void validate_motion(const Motion& motion, const std::string& source);

// Global joint positions (joint_count x 3) of one frame.
Points3d joint_positions(const Motion& motion, int64_t frame);

// Resamples to `frame_rate`: frame i is at time i / frame_rate; rotations are
// slerped (shortest arc), the root translation is interpolated linearly.
// Frame count = floor(duration * frame_rate) + 1, duration = (frames - 1) /
// source rate. Throws PLEAT_ERROR_INVALID_ARGUMENT for a rate not finite > 0.
Motion resample_motion(const Motion& motion, double frame_rate);

// Frames [first, first + count) as a motion of their own.
Motion cut_motion(const Motion& motion, int64_t first, int64_t count);

// The motion followed by `frames` copies of its last frame: a single-frame
// pose file becomes a clip that holds the pose. Throws
// PLEAT_ERROR_INVALID_ARGUMENT for an empty motion or a negative count.
Motion hold_motion(const Motion& motion, int64_t frames);

// ---- Joint-name mapping files -------------------------------------------------
// Text, one pair per line: "<source name>[|<alternative>...] <target name>",
// '#' starts a comment, blank lines are ignored. The first alternative present
// in the source skeleton is used. A target named twice is an error.
struct JointMapEntry {
  std::vector<std::string> sources;  // alternatives, in preference order
  std::string target;
  int32_t line = 0;
};
struct JointMap {
  std::string source;  // file name for messages
  std::vector<JointMapEntry> entries;
};

// PLEAT_ERROR_IO if unreadable; PLEAT_ERROR_FORMAT naming the line otherwise.
JointMap read_joint_map(const std::string& path);
JointMap parse_joint_map(const std::string& text, const std::string& source);

// Renames the joints of a skeleton that the map names (first alternative
// present -> target). Throws PLEAT_ERROR_INVALID_ARGUMENT if the result has a
// name twice.
void rename_joints(Skeleton* skeleton, const JointMap& map);

// ---- Retargeting ----------------------------------------------------------------
enum class MissingJoint { kError, kSkip };

struct RetargetOptions {
  const JointMap* map = nullptr;  // nullptr: pair joints by equal names only
  bool match_equal_names = true;  // also pair target joints that the map does not name with
                                  // equal-named source joints the map does not use
  MissingJoint missing_source = MissingJoint::kError;  // a map line none of whose sources exist
  MissingJoint missing_target = MissingJoint::kError;  // a map line whose target does not exist
  double root_scale = 0.0;  // 0: ratio of leg lengths (target / source), see hip_height
};

struct RetargetReport {
  std::vector<int32_t> source_of_target;  // per target joint: source joint or -1 (stays at rest)
  std::vector<std::string> unmapped_targets;
  std::vector<std::string> skipped_lines;  // "file:line: why", with MissingJoint::kSkip
  double root_scale = 1.0;
  double source_hip_height = 0.0;  // leg lengths used for the root scale
  double target_hip_height = 0.0;
};

// Leg length of the rest pose: from the root down to the lowest joint, as if
// the leg were straightened vertically (bones within 30 degrees of vertical
// count with their length, others, like pelvis and toe bones, with their drop). For a skeleton standing
// with straight vertical legs this is the height of the root above that joint.
double hip_height(const Skeleton& skeleton);

// Transfers `source` onto `target` (same frame rate and count). Per paired
// target joint t (source s): the alignment A_t is the shortest rotation taking
// t's rest bone direction (global frame; from t to its first paired
// descendants) to s's rest bone direction; the target's global rotation is
//   G_t = (G_s(frame) * G_s(rest)^-1) * A_t * G_t(rest)
// so every paired bone points where the source bone points, whatever the two
// rest poses (T-pose source, A-pose target). The root and joints without a
// usable direction (leaves) take the alignment of their nearest paired
// ancestor (identity at the root). Unpaired target joints keep their rest
// local rotation. The root follows its source joint's global position times
// the root scale: the ratio of leg lengths (as hip_height, from the paired
// root down to the lowest paired joint and its source joint). Throws PLEAT_ERROR_INVALID_ARGUMENT naming the
// map line for unknown names (see RetargetOptions), for an invalid motion (e.g. a NaN rotation, naming joint
// and frame) or skeleton, or an unpaired target root.
Motion retarget_motion(const Motion& source, const Skeleton& target, const RetargetOptions& options = {},
                       RetargetReport* report = nullptr);

// ---- Mirroring --------------------------------------------------------------------
// Left/right counterpart of a joint name: Left<->Right, left<->right,
// L<->R / l<->r prefixes before an upper-case letter (LHipJoint, lShldr),
// suffixes .L/.R, _L/_R, _l/_r. Names without a side come back unchanged.
std::string mirror_joint_name(const std::string& name);

// Mirrors a motion across the YZ plane (x -> -x) and swaps left and right
// joints (pairs found with mirror_joint_name; a joint whose counterpart is
// missing mirrors onto itself). The skeleton is kept: this assumes a
// left/right symmetric rest skeleton (CMU skeletons are within a few
// millimetres to a few centimetres). Mirroring twice gives the motion back.
Motion mirror_motion(const Motion& motion);

// Adds a steady turn about the vertical (y) axis: at frame f the root's
// global orientation and its horizontal step from frame f - 1 are rotated by
// theta(f), which grows at `degrees_per_second`. The rate eases in
// (smoothstep) over frames [ease_from, ease_from + ease_frames) and is 0
// before them. A walk becomes a walk along a circle of radius v / rate, a
// motion in place spins in place; joints below the root are unchanged.
// Throws PLEAT_ERROR_INVALID_ARGUMENT for a rate that is not finite or
// negative easing frames.
Motion turn_motion(const Motion& motion, double degrees_per_second, int64_t ease_from, int64_t ease_frames);

}  // namespace pleat
