#include "import_sequences.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "body/motion_ops.h"
#include "capi/pleat.h"
#include "character_clip.h"
#include "config_fields.h"
#include "io/atomic_file.h"
#include "io/obj_reader.h"
#include "io/point_cache.h"
#include "io/sequence.h"

namespace pleat::datagen {
namespace {

// import_sequences names the entry.
[[noreturn]] void reject(const std::string& what) {
  fail(PLEAT_ERROR_FORMAT, what);
}

SequenceData import_one(const ImportConfig& config, const ImportEntry& e) {
  SequenceData d;
  d.garment_rest = read_obj_file_order(e.garment);
  if (d.garment_rest.triangles.rows() == 0) reject("'" + e.garment + "' has no faces");
  d.garment_rest.vertices *= e.unit_scale;
  const int64_t n = d.garment_rest.vertex_count();

  const CacheHeader header = read_cache_header(e.cache, CacheFormat::automatic);
  if (header.vertex_count != n)
    reject("'" + e.cache + "' has " + std::to_string(header.vertex_count) + " vertices, the rest garment '" +
           e.garment + "' " + std::to_string(n) + " (vertex_count)");
  const double rate = e.cache_frame_rate > 0.0 ? e.cache_frame_rate : header.frame_rate;
  if (std::abs(rate - config.frame_rate) > 1e-3 * config.frame_rate)
    reject("'" + e.cache + "' runs at " + std::to_string(rate) + " fps, the data set at " +
           std::to_string(config.frame_rate) +
           " (frame_rate; resample the cache, or set cache_frame_rate if the file's rate is wrong)");
  const int64_t frames = header.frame_count;
  if (frames < 2)
    reject("'" + e.cache + "' holds " + std::to_string(frames) + " frame(s); a sequence needs 2");
  d.garment_frames.resize(static_cast<size_t>(frames * n * 3));
  read_cache(e.cache, CacheFormat::automatic, d.garment_frames.data(), 0, d.garment_frames.size());
  for (float& x : d.garment_frames) x = static_cast<float>(x * e.unit_scale);

  const CharacterClip character =
      load_character_clip(e.body, e.rig, e.shape, e.motion, e.map, config.frame_rate);
  const Body& body = character.body;
  const Motion& clip = character.clip;
  if (e.first + frames > clip.frame_count)
    reject("'" + e.cache + "' has " + std::to_string(frames) + " frames, the clip '" + e.motion + "' has " +
           std::to_string(clip.frame_count - std::min(e.first, clip.frame_count)) + " from frame " +
           std::to_string(e.first) + " at " + std::to_string(config.frame_rate) + " fps (first)");
  const Motion motion = cut_motion(clip, e.first, frames);

  // Frame 0 against the rest garment skinned to the clip: a cache in other
  // units, from another clip frame or of another body lands far away.
  const SkinWeights weights = nearest_vertex_weights(body, d.garment_rest.vertices);
  std::vector<double> skinned(static_cast<size_t>(n * 3));
  SkinningWorkspace workspace;
  skin_frames(d.garment_rest.vertices, weights, motion, 0, 1, &workspace, skinned.data(), skinned.size());
  double offset = 0.0;
  for (int64_t v = 0; v < n; ++v)
    offset += std::sqrt(std::pow(d.garment_frames[3 * v] - skinned[3 * v], 2) +
                        std::pow(d.garment_frames[3 * v + 1] - skinned[3 * v + 1], 2) +
                        std::pow(d.garment_frames[3 * v + 2] - skinned[3 * v + 2], 2));
  offset /= static_cast<double>(n);
  if (offset > config.max_offset)
    reject("frame 0 of '" + e.cache + "' lies " + std::to_string(offset * 100) +
           " cm (mean) from the rest garment skinned to frame " + std::to_string(e.first) + " of '" +
           e.motion + "': check unit_scale, first and the character (max_offset " +
           std::to_string(config.max_offset * 100) + " cm)");

  const Points3d posed = pose_body_frames(body, motion, 0, frames);
  d.body_frames.assign(posed.data(), posed.data() + posed.size());
  for (int64_t f = 0; f < frames; ++f) {
    for (int32_t j = 0; j < body.joint_count(); ++j) {
      const Eigen::Quaterniond& q = motion.frame(f)[j];
      d.rotations.insert(d.rotations.end(), {float(q.x()), float(q.y()), float(q.z()), float(q.w())});
    }
    for (int k = 0; k < 3; ++k) d.root_positions.push_back(static_cast<float>(motion.root_translation(f, k)));
  }
  SequenceMeta& m = d.meta;
  m.frame_rate = config.frame_rate;
  m.frame_count = frames;
  m.garment_name = e.garment_name;
  m.garment_source = e.garment;
  m.body_source = fs::absolute(e.body).string();
  m.body_kind = PLEAT_BODY_AUTO;
  m.body_rig = makehuman_rig(e.rig);
  m.shape = e.shape;
  m.motion_source = e.motion;
  m.motion_first_frame = e.first;
  m.joint_names = body.skeleton.names;
  m.split = e.split;
  m.simulator_json =
      Json{{"name", "imported"},         {"cache", e.cache},    {"cache_frame_rate", rate},
           {"unit_scale", e.unit_scale}, {"motion_map", e.map}, {"frame0_offset_cm", offset * 100}}
          .dump();
  return d;
}

}  // namespace

ImportConfig read_import_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(PLEAT_ERROR_IO, "import config '" + path + "': cannot open the file");
  const Json j = Json::parse(in, nullptr, false);
  if (j.is_discarded()) fail(PLEAT_ERROR_FORMAT, "import config '" + path + "': not valid JSON");
  const fs::path base = fs::path(path).parent_path();
  Fields root(j, path, "", "import config");
  ImportConfig c;
  c.source = path;
  c.output = resolve(base, root.text("output", "", true));
  c.frame_rate = root.number("frame_rate", c.frame_rate, 1, 1000);
  c.max_offset = root.number("max_offset", c.max_offset, 0.001, 10);
  const Json& list = root.list("sequences");
  const auto existing = [&](Fields& f, const std::string& key, bool required) {
    const std::string value = f.text(key, "", required);
    if (value.empty()) return value;
    const std::string p = resolve(base, value);
    if (!fs::exists(p)) f.bad("names '" + p + "', which does not exist", key);
    return p;
  };
  for (size_t i = 0; i < list.size(); ++i) {
    Fields f(list[i], path, "sequences[" + std::to_string(i) + "]", "import config");
    ImportEntry e;
    e.name = f.text("name", "", true);
    for (char ch : e.name)
      if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '.'))
        f.bad("may hold only letters, digits, '_', '-' and '.' (it names a folder)", "name");
    e.split = f.text("split", e.split);
    if (e.split != "train" && e.split != "validation" && e.split != "test")
      f.bad("must be train, validation or test", "split");
    e.garment = existing(f, "garment", true);
    e.garment_name = f.text("garment_name", fs::path(e.garment).stem().string());
    e.body = existing(f, "body", true);
    e.rig = f.text("rig", e.rig);
    if (e.rig != "cmu_mb" && e.rig != "default") f.bad("must be cmu_mb or default", "rig");
    if (f.has("shape")) {
      const Json& shape = f.at("shape");
      if (!shape.is_object()) f.bad("must be an object of name: value", "shape");
      for (const auto& [name, value] : shape.items()) {
        if (!value.is_number()) f.bad("must be a number", "shape." + name);
        e.shape.emplace_back(name, value.get<double>());
      }
    }
    e.motion = existing(f, "motion", true);
    e.map = existing(f, "map", false);
    e.first = f.integer("first", 0, 0, 100000000);
    e.cache = f.text("cache", "", true);
    e.cache = resolve(base, e.cache);
    if (e.cache.find('#') == std::string::npos && !fs::exists(e.cache))
      f.bad("names '" + e.cache + "', which does not exist", "cache");
    e.cache_frame_rate = f.number("cache_frame_rate", 0.0, 0.0, 1000);
    e.unit_scale = f.number("unit_scale", 1.0, 1e-6, 1e6);
    f.done();
    for (const ImportEntry& other : c.sequences)
      if (other.name == e.name) f.bad("repeats the name '" + e.name + "'", "name");
    c.sequences.push_back(std::move(e));
  }
  root.done();
  return c;
}

void import_sequences(const ImportConfig& config, bool progress) {
  fs::create_directories(config.output);
  Json splits = {{"train", Json::array()}, {"validation", Json::array()}, {"test", Json::array()}};
  for (size_t i = 0; i < config.sequences.size(); ++i) {
    const ImportEntry& e = config.sequences[i];
    SequenceData d;
    try {
      d = import_one(config, e);
    } catch (const Error& error) {
      fail(error.status(), config.source + ": sequence '" + e.name + "': " + error.what());
    }
    write_sequence(config.output + "/" + e.name, d);
    splits[e.split].push_back(e.name);
    if (progress)
      std::fprintf(stderr, "[%zu/%zu] %s (%s): %lld frames of %d vertices\n", i + 1, config.sequences.size(),
                   e.name.c_str(), e.split.c_str(), static_cast<long long>(d.meta.frame_count),
                   d.garment_rest.vertex_count());
  }
  AtomicFile f(config.output + "/splits.json");
  f.write(splits.dump(1) + "\n");
  f.commit();
}

}  // namespace pleat::datagen
