#pragma once
// The manifest of `pleat convert`: garments x characters x clips, each a
// named entry or a glob that expands to one entry per file, and the output
// settings. Parsing checks every field and that every named file exists, so
// a bad manifest fails (exit 2) before any work.
#include <map>
#include <string>
#include <vector>

namespace pleat_cli {

struct ConvertGarment {
  std::string name, mesh, model;  // model: this garment's own, else the manifest's
  double unit_scale = 0.0;
};

struct ConvertCharacter {
  std::string name, body, rig = "cmu_mb";
  std::map<std::string, double> shape;
};

struct ConvertClip {
  std::string name, motion, map;
  size_t first = 0, frames = 0;  // frames 0: to the end of the clip
};

struct ConvertManifest {
  std::string path;                  // of the manifest, for messages
  std::string output;                // folder
  std::vector<std::string> formats;  // pc2, mdd, obj, gltf, glb, usda
  std::string stage = "full";
  unsigned threads = 1, top_k = 0;
  double body_collision = 0.0;  // metres; > 0: the body-collision post-pass
  std::vector<ConvertGarment> garments;
  std::vector<ConvertCharacter> characters;
  std::vector<ConvertClip> clips;
};

struct ConvertJob {
  std::string name;  // garment-character-clip, also the stem of every output
  const ConvertGarment* garment;
  const ConvertCharacter* character;
  const ConvertClip* clip;
};

// Reads and checks the manifest (paths relative to it). Throws CliError with
// exit code 2 naming the file and field.
ConvertManifest read_convert_manifest(const std::string& path);

// Every garment x character x clip, in manifest order (garments outermost).
std::vector<ConvertJob> convert_jobs(const ConvertManifest& manifest);

// The output path of a job in one format; an OBJ sequence is a pattern in the
// job's own folder.
std::string convert_output(const ConvertManifest& manifest, const ConvertJob& job, const std::string& format);

}  // namespace pleat_cli
