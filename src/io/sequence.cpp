#include "io/sequence.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "capi/pleat.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "io/obj_reader.h"
#include "io/obj_writer.h"
#include "io/point_cache.h"

namespace pleat {
namespace {

using Json = nlohmann::json;

[[noreturn]] void bad(const std::string& dir, const std::string& what) {
  fail(PLEAT_ERROR_FORMAT, "sequence '" + dir + "': " + what);
}

void check_finite(const std::vector<float>& v, const std::string& what) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      fail(PLEAT_ERROR_INVALID_ARGUMENT, what + " value " + std::to_string(i) + " is not finite");
}

void check_size(const std::vector<float>& v, size_t expected, const std::string& what) {
  if (v.size() != expected)
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         what + " has " + std::to_string(v.size()) + " values, expected " + std::to_string(expected));
}

Json meta_json(const SequenceMeta& m) {
  Json shape = Json::object();
  for (const auto& [name, value] : m.shape) shape[name] = value;
  Json j = {
      {"format", "pleat-sequence"},
      {"version", kSequenceFormatVersion},
      {"frame_rate", m.frame_rate},
      {"frame_count", m.frame_count},
      {"garment", {{"name", m.garment_name}, {"source", m.garment_source}}},
      {"body", {{"source", m.body_source}, {"kind", m.body_kind}, {"rig", m.body_rig}, {"shape", shape}}},
      {"motion",
       {{"source", m.motion_source},
        {"first_frame", m.motion_first_frame},
        {"mirrored", m.mirrored},
        {"joints", m.joint_names}}},
      {"split", m.split}};
  j["simulator"] = m.simulator_json.empty() ? Json::object() : Json::parse(m.simulator_json);
  return j;
}

template <typename T>
T field(const Json& j, const char* key, const std::string& dir, const std::string& where) {
  if (!j.contains(key)) bad(dir, "meta.json: " + where + key + " is missing");
  try {
    return j.at(key).get<T>();
  } catch (const Json::exception&) {
    bad(dir, "meta.json: " + where + key + " has the wrong type");
  }
}

SequenceMeta parse_meta(const std::string& dir) {
  std::ifstream in(dir + "/meta.json");
  if (!in) fail(PLEAT_ERROR_IO, "sequence '" + dir + "': cannot open meta.json");
  Json j;
  try {
    j = Json::parse(in);
  } catch (const Json::exception& e) {
    bad(dir, std::string("meta.json is not valid JSON: ") + e.what());
  }
  if (!j.is_object() || j.value("format", "") != "pleat-sequence")
    bad(dir, "meta.json: format is not 'pleat-sequence'");
  const int version = field<int>(j, "version", dir, "");
  if (version > kSequenceFormatVersion)
    fail(PLEAT_ERROR_UNSUPPORTED_VERSION, "sequence '" + dir + "': version " + std::to_string(version) +
                                              " is newer than this pleat reads (" +
                                              std::to_string(kSequenceFormatVersion) + ")");
  SequenceMeta m;
  m.frame_rate = field<double>(j, "frame_rate", dir, "");
  m.frame_count = field<int64_t>(j, "frame_count", dir, "");
  if (!(m.frame_rate > 0 && m.frame_rate <= 1000)) bad(dir, "meta.json: frame_rate is out of range");
  if (m.frame_count < 1) bad(dir, "meta.json: frame_count must be positive");
  const Json garment = field<Json>(j, "garment", dir, "");
  m.garment_name = field<std::string>(garment, "name", dir, "garment.");
  m.garment_source = field<std::string>(garment, "source", dir, "garment.");
  const Json body = field<Json>(j, "body", dir, "");
  m.body_source = field<std::string>(body, "source", dir, "body.");
  m.body_kind = field<uint32_t>(body, "kind", dir, "body.");
  m.body_rig = field<uint32_t>(body, "rig", dir, "body.");
  const Json shape = field<Json>(body, "shape", dir, "body.");
  if (!shape.is_object()) bad(dir, "meta.json: body.shape is not an object");
  for (const auto& [name, value] : shape.items()) {
    if (!value.is_number()) bad(dir, "meta.json: body.shape." + name + " is not a number");
    m.shape.emplace_back(name, value.get<double>());
  }
  const Json motion = field<Json>(j, "motion", dir, "");
  m.motion_source = field<std::string>(motion, "source", dir, "motion.");
  m.motion_first_frame = field<int64_t>(motion, "first_frame", dir, "motion.");
  m.mirrored = field<bool>(motion, "mirrored", dir, "motion.");
  m.joint_names = field<std::vector<std::string>>(motion, "joints", dir, "motion.");
  if (m.joint_names.empty()) bad(dir, "meta.json: motion.joints is empty");
  m.split = j.value("split", "");
  if (j.contains("simulator")) m.simulator_json = j["simulator"].dump();
  return m;
}

std::vector<float> read_frames(const std::string& dir, const std::string& file, int64_t frames,
                               int64_t* vertices) {
  const std::string path = dir + "/" + file;
  const CacheHeader h = read_cache_header(path, CacheFormat::pc2);
  if (h.frame_count != frames)
    bad(dir,
        file + " has " + std::to_string(h.frame_count) + " frames, meta.json says " + std::to_string(frames));
  std::vector<float> out(static_cast<size_t>(h.frame_count * h.vertex_count * 3));
  read_cache(path, CacheFormat::pc2, out.data(), 0, out.size());
  *vertices = h.vertex_count;
  return out;
}

}  // namespace

int64_t SequenceData::body_vertex_count() const {
  return meta.frame_count > 0 ? static_cast<int64_t>(body_frames.size()) / (meta.frame_count * 3) : 0;
}

void write_sequence(const std::string& dir, const SequenceData& d) {
  const SequenceMeta& m = d.meta;
  const size_t frames = static_cast<size_t>(m.frame_count), joints = m.joint_names.size();
  const size_t garment_vertices = static_cast<size_t>(d.garment_rest.vertex_count());
  if (frames == 0 || joints == 0 || garment_vertices == 0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         "sequence '" + dir + "': frame, joint and garment vertex counts must be positive");
  check_size(d.garment_frames, frames * garment_vertices * 3, "garment frames");
  if (d.body_frames.empty() || d.body_frames.size() % (frames * 3) != 0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "body frames hold no whole number of frames");
  check_size(d.rotations, frames * joints * 4, "rotations");
  check_size(d.root_positions, frames * 3, "root positions");
  for (const auto* v : {&d.garment_frames, &d.body_frames, &d.rotations, &d.root_positions})
    check_finite(*v, "sequence '" + dir + "'");
  std::filesystem::create_directories(dir);
  const Points3f rest_points = d.garment_rest.vertices.cast<float>();
  write_obj(dir + "/garment.obj", rest_points.data(), garment_vertices, d.garment_rest.triangles);
  write_cache(dir + "/garment.pc2", CacheFormat::pc2, d.garment_frames.data(), frames, garment_vertices, 0,
              m.frame_rate, nullptr);
  write_cache(dir + "/body.pc2", CacheFormat::pc2, d.body_frames.data(), frames,
              d.body_frames.size() / (frames * 3), 0, m.frame_rate, nullptr);
  {
    AtomicFile poses(dir + "/poses.bin");
    poses.write(d.rotations.data(), d.rotations.size() * sizeof(float));
    poses.write(d.root_positions.data(), d.root_positions.size() * sizeof(float));
    poses.commit();
  }
  AtomicFile meta(dir + "/meta.json");
  meta.write(meta_json(m).dump(2) + "\n");
  meta.commit();
}

std::string default_dataset_dir(const std::string& name) {
  namespace fs = std::filesystem;
  if (const char* d = std::getenv("PLEAT_DATA_DIR"); d && *d) return (fs::path(d) / name).string();
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
    return (fs::path(x) / "pleat" / "datasets" / name).string();
  const char* home = std::getenv("HOME");
  return (fs::path(home && *home ? home : ".") / ".cache" / "pleat" / "datasets" / name).string();
}

std::string clip_name(const std::string& motion_source, double speed, double turn) {
  std::ostringstream name;
  name << std::filesystem::path(motion_source).stem().string();
  if (speed != 1.0) name << "x" << speed;
  if (turn != 0.0) name << "t" << turn;
  return name.str();
}

bool sequence_complete(const std::string& dir) {
  return std::filesystem::is_regular_file(dir + "/meta.json");
}

SequenceData read_sequence(const std::string& dir) {
  SequenceData d;
  d.meta = parse_meta(dir);
  const int64_t frames = d.meta.frame_count, joints = static_cast<int64_t>(d.meta.joint_names.size());
  d.garment_rest = read_obj_file_order(dir + "/garment.obj");  // errors name the path
  const Points3d& order = d.garment_rest.vertices;
  int64_t garment_vertices = 0, body_vertices = 0;
  d.garment_frames = read_frames(dir, "garment.pc2", frames, &garment_vertices);
  if (garment_vertices != order.rows())
    bad(dir, "garment.pc2 has " + std::to_string(garment_vertices) + " vertices, garment.obj " +
                 std::to_string(order.rows()));
  d.body_frames = read_frames(dir, "body.pc2", frames, &body_vertices);
  std::ifstream poses(dir + "/poses.bin", std::ios::binary);
  if (!poses) fail(PLEAT_ERROR_IO, "sequence '" + dir + "': cannot open poses.bin");
  d.rotations.resize(static_cast<size_t>(frames * joints * 4));
  d.root_positions.resize(static_cast<size_t>(frames * 3));
  poses.read(reinterpret_cast<char*>(d.rotations.data()),
             static_cast<std::streamsize>(d.rotations.size() * 4));
  poses.read(reinterpret_cast<char*>(d.root_positions.data()),
             static_cast<std::streamsize>(d.root_positions.size() * 4));
  if (!poses || poses.peek() != std::char_traits<char>::eof())
    bad(dir, "poses.bin does not hold " + std::to_string(frames) + " frames of " + std::to_string(joints) +
                 " joints (" + std::to_string((d.rotations.size() + d.root_positions.size()) * 4) +
                 " bytes)");
  try {
    check_finite(d.rotations, "poses.bin");
    check_finite(d.root_positions, "poses.bin");
  } catch (const Error& e) {
    bad(dir, e.what());
  }
  return d;
}

}  // namespace pleat
