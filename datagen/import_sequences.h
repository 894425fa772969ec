#pragma once
// `pleat import-sequences config.json`: training sequences (io/sequence.h)
// from any simulator's point caches. Each entry names the rest garment (an
// OBJ in the cache's vertex order), the character, the clip the simulation
// was driven by and the cache (PC2, MDD, OBJ sequence, glTF); pleat poses the
// body with the clip and checks that the cache fits: vertex count, frame
// rate, frame count, finite values and that frame 0 lies on the garment
// skinned to the clip (units and alignment). docs/pipeline.md.
#include <map>
#include <string>
#include <vector>

namespace pleat::datagen {

struct ImportEntry {
  std::string name, split = "train";
  std::string garment, garment_name;  // the rest OBJ; the name sequences of one garment share
  std::string body, rig = "cmu_mb";
  std::vector<std::pair<std::string, double>> shape;
  std::string motion, map;
  int64_t first = 0;  // the clip frame (at frame_rate) the cache's frame 0 shows
  std::string cache;
  double cache_frame_rate = 0.0;  // 0: what the file says (PC2 and OBJ store none: 30)
  double unit_scale = 1.0;        // applied to the rest garment and the cache
};

struct ImportConfig {
  std::string source, output;
  double frame_rate = 30.0;
  double max_offset = 0.1;  // metres: frame 0's mean distance from the skinned garment
  std::vector<ImportEntry> sequences;
};

// Throws PLEAT_ERROR_FORMAT naming the file and field, PLEAT_ERROR_IO for a
// missing file.
ImportConfig read_import_config(const std::string& path);

// Writes output/<name>/ per entry and output/splits.json, in order; the
// first entry that fails the checks throws (naming the entry, the file and
// the field) and leaves the sequences before it and no splits.json.
// progress: one line per sequence on stderr.
void import_sequences(const ImportConfig& config, bool progress);

}  // namespace pleat::datagen
