#pragma once
// `pleat preview`: a PNG contact sheet (io/contact_sheet.h) of a few frames,
// the garment over the body, front and side: of a training sequence folder
// (simulated or imported), or of a bake (any point cache, with the garment
// mesh for its faces and the body and clip that drove it). The datagen run
// writes one of its data set; docs/pipeline.md.
#include <string>
#include <utility>
#include <vector>

#include "io/sequence.h"

namespace pleat::datagen {

// `count` frames spread evenly over a sequence folder's frames.
void preview_sequence(const std::string& dir, const std::string& png, int count);

struct BakePreview {
  std::string cache, garment;  // any point cache; the garment mesh (OBJ) in its vertex order
  std::string body, rig = "cmu_mb", motion, map;
  std::vector<std::pair<std::string, double>> shape;
  int64_t first = 0;  // clip frame of the cache's frame 0
  double frame_rate = 30.0;
};
void preview_bake(const BakePreview& bake, const std::string& png, int count);

// Frames f_i = round(i (frames - 1) / (count - 1)) for i < count, at most frames.
std::vector<int64_t> preview_frames(int64_t frames, int count);

}  // namespace pleat::datagen
