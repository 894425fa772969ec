#pragma once
// One simulated training sequence on disk (DESIGN §8, docs/data.md): a
// folder with
//   meta.json     what made it: garment, body (path, kind, rig, shape),
//                 motion (source, first frame, mirroring, joint names), frame
//                 rate, frame count, simulator settings and version
//   garment.obj   the rest garment, metres; its vertex order ("v" lines) is
//                 the order of garment.pc2
//   garment.pc2   the simulated garment per frame
//   body.pc2      the posed body per frame (the body's rest-mesh order)
//   poses.bin     little-endian float32: frames x joints x (x, y, z, w)
//                 rotations relative to rest, then frames x 3 root positions
//                 (metres), joints in meta.json's order
// meta.json is written last, so a folder with one is complete.
#include <string>
#include <utility>
#include <vector>

#include "core/mesh.h"

namespace pleat {

constexpr int kSequenceFormatVersion = 1;

struct SequenceMeta {
  double frame_rate = 30.0;
  int64_t frame_count = 0;
  std::string garment_name, garment_source;
  std::string body_source;  // a MakeHuman folder, an SMPL-layout .npz or a rigged mesh
  uint32_t body_kind = 0;   // PLEAT_BODY_*
  uint32_t body_rig = 0;    // PLEAT_RIG_*
  std::vector<std::pair<std::string, double>> shape;
  std::string motion_source;
  int64_t motion_first_frame = 0;
  bool mirrored = false;
  std::vector<std::string> joint_names;
  std::string split;           // "train", "validation", "test" or empty
  std::string simulator_json;  // the simulator's settings, a JSON object kept verbatim
};

struct SequenceData {
  SequenceMeta meta;
  TriMesh garment_rest;               // as in garment.obj (not welded)
  std::vector<float> garment_frames;  // frames x garment vertices x 3
  std::vector<float> body_frames;     // frames x body vertices x 3
  std::vector<float> rotations;       // frames x joints x 4
  std::vector<float> root_positions;  // frames x 3
  int64_t body_vertex_count() const;
};

// Every file atomically, meta.json last. Throws PLEAT_ERROR_INVALID_ARGUMENT
// when the arrays disagree with the counts (naming the array) or hold a
// non-finite value, PLEAT_ERROR_IO when a file cannot be written.
void write_sequence(const std::string& dir, const SequenceData& data);

// Where a data set named `name` lives unless told otherwise (the cache folder
// that `pleat datagen` writes and training configs name with "dataset_name"):
// $PLEAT_DATA_DIR/<name>, else $XDG_CACHE_HOME/pleat/datasets/<name>, else
// ~/.cache/pleat/datasets/<name>.
std::string default_dataset_dir(const std::string& name);

// The name datagen gives a clip, and `pleat-train evaluate --by-clip` groups
// sequences by: the motion file's stem, then x<speed> unless it is 1 and
// t<turn> (deg/s) unless it is 0 ("01_01", "01_01x1.3", "01_01t360").
std::string clip_name(const std::string& motion_source, double speed, double turn);

// True if `dir` holds a complete sequence (its meta.json exists).
bool sequence_complete(const std::string& dir);

// Reads and checks a sequence: PLEAT_ERROR_IO for a missing file,
// PLEAT_ERROR_FORMAT (naming the file and field) for a malformed meta.json,
// counts that disagree between the files, or a non-finite value.
SequenceData read_sequence(const std::string& dir);

}  // namespace pleat
