#pragma once
// Which sequences a data set holds: every clip cut into segments (and
// mirrored), segments drawn round-robin per split with the clips interleaved,
// garment x shape pairs drawn round-robin alongside (ordered so that
// consecutive pairs differ in garment and shape: a short split still sees
// many of both). Deterministic: the same config gives the same plan.
//
// Splits (the paper's protocol): a clip's segments all go to its split, so no
// motion is on both sides; "held_out" sequences use garments that no other
// split has, on clips of any split but validation, and are labelled "test".
#include <cstdint>
#include <string>
#include <vector>

#include "config.h"

namespace pleat::datagen {

struct Segment {
  size_t motion = 0;
  int64_t first = 0, count = 0;  // frames at the config's frame rate
  bool mirrored = false;
};

struct Job {
  std::string name;   // the sequence folder: <garment>-<shape>-<motion>-<first>[m]
  std::string split;  // "train", "validation" or "test"
  bool held_out_garment = false;
  std::string twin_of;  // a twin job (config.twins): the name of the job it repeats
  size_t garment = 0, shape = 0;
  Segment segment;
};

// Segments of one clip of `frames` frames: up to segments_per_clip of
// segment_frames each, spread evenly; a clip shorter than one segment gives
// one segment of all its frames if it has min_segment_frames, else none.
std::vector<Segment> clip_segments(const Config& config, size_t motion, int64_t frames);

// motion_frames[m]: frame count of motion m at the config's frame rate.
// With config.twins, every job of that split gets a twin, named
// `<name>.twin`, planned after all the others.
// Throws PLEAT_ERROR_INVALID_ARGUMENT naming the split when its clips give no
// segment. No combination (garment, shape, segment) is planned twice, so a
// split asking for more than it has gets fewer.
std::vector<Job> plan_jobs(const Config& config, const std::vector<int64_t>& motion_frames);

}  // namespace pleat::datagen
