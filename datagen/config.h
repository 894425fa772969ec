#pragma once
// `pleat datagen` configuration (docs/datagen.md): what to simulate (garments,
// body shapes, motion clips, how many sequences per split) and how (frame
// rate, settling, Blender cloth and collision settings, the acceptance check).
// Every path in the file is relative to the file, or to "assets" for the
// body, garments and motions.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pleat::datagen {

// Blender cloth modifier settings (bpy ClothSettings; stiffness in Blender's
// units, mass in kg per vertex).
struct ClothSettings {
  int quality = 5;  // solver steps per frame
  double mass = 0.3, air_damping = 1.0;
  double tension_stiffness = 15, compression_stiffness = 15, shear_stiffness = 5, bending_stiffness = 0.5;
  double tension_damping = 5, compression_damping = 5, shear_damping = 5, bending_damping = 0.5;
  double pin_stiffness = 1.0;
};

struct CollisionSettings {
  int quality = 2;
  double distance = 0.005;               // cloth-body minimum distance, m
  double body_thickness = 0.005;         // COLLISION thickness_outer, m
  double body_thickness_inner = 0.01;    // COLLISION thickness_inner, m
  double friction = 5.0, damping = 0.0;  // COLLISION cloth_friction, damping
  bool self_collision = false;
  double self_distance = 0.005, self_friction = 5.0;
};

// A simulation is rejected when, on any kept frame, a garment vertex is further
// than max_distance from the nearest body vertex (explosion, a garment that
// fell off), or more than max_penetrating_fraction of the vertices are more
// than max_penetration inside the body; or when, averaged over the kept
// frames, more than max_slipped_fraction of the vertices have slipped: moved
// more than slip_distance further from the body vertex they sat nearest at
// rest than they were at rest (a sleeve the arm passed through, a jacket
// that slid off the shoulders; docs/datagen.md, "Garments that come off").
// A body vertex faster than max_body_speed between two kept frames rejects
// it too: no person moves like that, a clip that jumps does (a reference
// pose as its first frame; skip_frames). The slip and speed checks are not
// part of a job's hash: kept sequences are checked again from their files,
// so changing them never re-simulates.
struct CheckSettings {
  double max_distance = 0.3;
  double max_penetration = 0.02;
  double max_penetrating_fraction = 0.02;
  double max_body_speed = 15.0;  // m/s; CMU's fastest hands reach about 8 m/s, a reference-pose jump 20-36
  double slip_distance = 0.15;
  double max_slipped_fraction = 1.0;  // off: a long skirt's hem legitimately leaves the shin it sat at
};

// The noise floor: every sequence of `split` is simulated a second time
// with the cloth a little heavier and a longer rest lead-in. What differs
// between the two is no function of the motion, so no pose-driven model can
// predict it; the trainer's reports put it next to LBS.
struct TwinSettings {
  std::string split;  // "train", "validation" or "test"; empty: no twins
  double mass_scale = 1.001;
  int64_t extra_rest_frames = 10;
};

struct GarmentSpec {
  std::string name;
  std::string mhclo;      // absolute
  bool held_out = false;  // only in the test split (garments unseen in training)
  // Pinned vertices follow the skinned body: those of each piece's top band
  // (pin_band below its highest point) closer than pin_distance to the body
  // (sequence_inputs.h pinned_vertices); pin_distance 0 pins nothing.
  double pin_distance = 0.01;
  double pin_band = 0.05;
  // A longer variant of a skirt or dress (geometry augmentation): the part of
  // the fitted garment below `stretch_below` of its height (a fraction,
  // measured up from its lowest point) is stretched downwards by
  // `stretch_factor` (sequence_inputs.h stretch_hem). 1 = the garment as bound.
  double stretch_below = 0.0;
  double stretch_factor = 1.0;
  bool stretched() const { return stretch_factor != 1.0; }
};

struct ShapeSpec {
  std::string name;
  std::vector<std::pair<std::string, double>> values;  // named β entries; the rest keep defaults
};

struct MotionSpec {
  std::string name;         // file stem unless given
  std::string source;       // absolute .bvh path
  std::string map;          // absolute joint map (io/motion_ops.h format), or empty: equal names
  std::string split;        // "train", "validation" or "test": all its segments go there
  int64_t skip_frames = 0;  // source frames dropped first (CMU cgspeed files open with a reference pose)
  int64_t take_frames = 0;  // source frames kept after those, 0: to the end (splits one take by time)
  int64_t hold_frames = 0;  // the last pose held this long after the clip (a pose file: a static clip)
  double speed = 1.0;       // playback rate: 1.25 plays the clip 25 % faster (new dynamics, simulated)
  double turn = 0.0;  // deg/s of steady turn about the vertical added to the clip (motion_ops.h turn_motion)
};

struct Config {
  std::string path;    // the config file
  std::string name;    // the data set's name (default output folder)
  std::string output;  // absolute; empty: the cache folder (output_dir)
  std::string blender = "blender";
  std::string body;  // MakeHuman assets folder, absolute
  // What the cloth collides with in Blender: a MakeHuman proxy (.proxy, or
  // any .mhclo) fitted to each shape and skinned like the garments, absolute;
  // empty: the body itself. Body collision is ~90% of Blender's time and
  // scales with the collider, so a 1,600-vertex proxy is much cheaper than
  // the 13,380-vertex body. The check still measures against the body.
  std::string collider;
  std::string rig = "cmu_mb";
  double frame_rate = 30.0;
  int64_t segment_frames = 120;     // kept frames per sequence
  int64_t segments_per_clip = 2;    // cut from each clip, evenly spaced
  int64_t min_segment_frames = 60;  // a shorter clip gives one segment of all its frames if it has this many
  bool mirror = true;               // also every segment mirrored left/right
  int64_t rest_frames = 10;         // still in the rest pose, settling under gravity
  int64_t blend_frames = 30;        // rest pose -> first motion frame; both discarded
  int64_t train = 0, validation = 0, test = 0, held_out = 0;  // sequences per split
  std::vector<GarmentSpec> garments;
  std::vector<ShapeSpec> shapes;
  std::vector<MotionSpec> motions;
  ClothSettings cloth;
  CollisionSettings collision;
  CheckSettings check;
  TwinSettings twins;
};

// The settings a twin job runs with: config with the cloth's mass scaled and
// the rest lead-in lengthened by config.twins.
Config twin_config(const Config& config);

// Throws PLEAT_ERROR_IO for an unreadable file and PLEAT_ERROR_FORMAT naming
// the file and field: invalid JSON, an unknown key, a wrong type, a value out
// of range, a missing asset file, duplicate names, or a split with sequences
// asked for but nothing to draw them from.
Config read_config(const std::string& path);
Config parse_config(const std::string& text, const std::string& path);

// The resolved output folder: config.output, else default_dataset_dir(name)
// (io/sequence.h: the cache folder).
std::string output_dir(const Config& config);

}  // namespace pleat::datagen
