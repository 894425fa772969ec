#include "convert_manifest.h"

#include <glob.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "cli.h"

namespace pleat_cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

const std::set<std::string> kFormats = {"pc2", "mdd", "obj", "gltf", "glb", "usda"};

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)), dir_(fs::path(path_).parent_path()) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw CliError{path_ + ": " + field + ": " + what, 2};
  }

  // Only the listed members; a typo fails instead of being ignored.
  void only(const Json& object, const std::string& field, const std::set<std::string>& members) const {
    if (!object.is_object()) fail(field, "must be an object");
    for (const auto& item : object.items())
      if (!members.count(item.key())) fail(field + "." + item.key(), "is not a known setting");
  }

  std::string text(const Json& object, const std::string& field, const std::string& key,
                   const std::string& fallback) const {
    if (!object.contains(key)) return fallback;
    if (!object[key].is_string() || object[key].get<std::string>().empty())
      fail(field + "." + key, "must be a non-empty string");
    return object[key].get<std::string>();
  }

  double number(const Json& object, const std::string& field, const std::string& key, double fallback,
                double lo, double hi) const {
    if (!object.contains(key)) return fallback;
    if (!object[key].is_number()) fail(field + "." + key, "must be a number");
    const double v = object[key].get<double>();
    if (!(v >= lo && v <= hi))
      fail(field + "." + key,
           std::to_string(v) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  }

  size_t count(const Json& object, const std::string& field, const std::string& key) const {
    const double v = number(object, field, key, 0.0, 0.0, 1e9);
    if (v != static_cast<double>(static_cast<size_t>(v))) fail(field + "." + key, "must be a whole number");
    return static_cast<size_t>(v);
  }

  // A path relative to the manifest that must exist.
  std::string existing(const std::string& field, const std::string& value) const {
    const std::string p = resolve(value);
    std::error_code error;
    if (!fs::exists(p, error)) fail(field, "'" + p + "' does not exist");
    return p;
  }

  // The files a path names: itself (checked to exist), or every match of a
  // glob, sorted; none is an error.
  std::vector<std::string> expand(const std::string& field, const std::string& value) const {
    if (value.find_first_of("*?[") == std::string::npos) return {existing(field, value)};
    const std::string pattern = resolve(value);
    glob_t matches{};
    const int status = ::glob(pattern.c_str(), 0, nullptr, &matches);
    std::vector<std::string> files(matches.gl_pathv, matches.gl_pathv + matches.gl_pathc);
    ::globfree(&matches);
    if (status != 0 || files.empty()) fail(field, "no file matches '" + pattern + "'");
    return files;  // glob(3) sorts them
  }

  // The entry's name: given, or the file's stem; letters, digits, '_', '.'
  // and '-' only, since it names output files.
  std::string name(const Json& object, const std::string& field, const std::string& file,
                   bool from_glob) const {
    if (from_glob && object.contains("name")) fail(field + ".name", "cannot name the many entries of a glob");
    std::string n = text(object, field, "name", fs::path(file).stem().string());
    if (n.empty()) n = fs::path(file).filename().string();
    for (char c : n)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-'))
        fail(field + ".name", "'" + n + "' may hold only letters, digits, '_', '.' and '-' (it names files)");
    return n;
  }

  std::string resolve(const std::string& value) const {
    return fs::path(value).is_absolute() ? value : (dir_ / value).lexically_normal().string();
  }

 private:
  std::string path_;
  fs::path dir_;
};

template <typename Entry>
void require_unique(const Reader& r, const std::vector<Entry>& entries, const std::string& list) {
  std::set<std::string> seen;
  for (const Entry& e : entries)
    if (!seen.insert(e.name).second) r.fail(list, "two entries are named '" + e.name + "'");
}

const Json& list(const Reader& r, const Json& root, const std::string& key) {
  if (!root.contains(key) || !root[key].is_array() || root[key].empty())
    r.fail(key, "must be a non-empty array");
  return root[key];
}

}  // namespace

ConvertManifest read_convert_manifest(const std::string& path) {
  ConvertManifest m;
  m.path = path;
  const Reader r(path);
  std::ifstream in(path);
  if (!in) throw CliError{"cannot read the manifest '" + path + "'", 2};
  Json root = Json::parse(in, nullptr, false);
  if (root.is_discarded()) throw CliError{path + ": not valid JSON", 2};
  r.only(root, "manifest",
         {"output", "formats", "stage", "threads", "top_k", "body_collision", "model", "garments",
          "characters", "clips"});
  m.output = r.resolve(r.text(root, "manifest", "output", "converted"));
  m.stage = r.text(root, "manifest", "stage", "full");
  stage_of(m.stage);
  m.threads = static_cast<unsigned>(r.number(root, "manifest", "threads", 1, 0, 256));
  m.top_k = static_cast<unsigned>(r.number(root, "manifest", "top_k", 0, 0, 1 << 20));
  m.body_collision = r.number(root, "manifest", "body_collision", 0.0, 0.0, 1.0);
  const Json formats = root.value("formats", Json::array({"pc2"}));
  if (!formats.is_array() || formats.empty()) r.fail("formats", "must be a non-empty array");
  for (const Json& f : formats) {
    if (!f.is_string() || !kFormats.count(f.get<std::string>()))
      r.fail("formats", f.dump() + " is not one of pc2, mdd, obj, gltf, glb, usda");
    m.formats.push_back(f.get<std::string>());
  }
  const std::string default_model =
      root.contains("model") ? r.existing("model", r.text(root, "manifest", "model", "")) : "";

  const Json& garments = list(r, root, "garments");
  for (size_t i = 0; i < garments.size(); ++i) {
    const std::string field = "garments[" + std::to_string(i) + "]";
    r.only(garments[i], field, {"name", "mesh", "unit_scale", "model"});
    const std::string mesh = r.text(garments[i], field, "mesh", "");
    if (mesh.empty()) r.fail(field + ".mesh", "is required");
    ConvertGarment g;
    g.unit_scale = r.number(garments[i], field, "unit_scale", 0.0, 0.0, 1e6);
    g.model = garments[i].contains("model")
                  ? r.existing(field + ".model", r.text(garments[i], field, "model", ""))
                  : default_model;
    if (g.model.empty()) r.fail(field + ".model", "is required when the manifest names no model");
    const std::vector<std::string> files = r.expand(field + ".mesh", mesh);
    for (const std::string& file : files) {
      g.mesh = file;
      g.name = r.name(garments[i], field, file, mesh.find_first_of("*?[") != std::string::npos);
      m.garments.push_back(g);
    }
  }
  const Json& characters = list(r, root, "characters");
  for (size_t i = 0; i < characters.size(); ++i) {
    const std::string field = "characters[" + std::to_string(i) + "]";
    r.only(characters[i], field, {"name", "body", "rig", "shape"});
    const std::string body = r.text(characters[i], field, "body", "");
    if (body.empty()) r.fail(field + ".body", "is required");
    ConvertCharacter c;
    c.rig = r.text(characters[i], field, "rig", "cmu_mb");
    if (c.rig != "cmu_mb" && c.rig != "default") r.fail(field + ".rig", "must be cmu_mb or default");
    if (characters[i].contains("shape")) {
      const Json& shape = characters[i]["shape"];
      if (!shape.is_object()) r.fail(field + ".shape", "must be an object of name: value");
      for (const auto& item : shape.items())
        c.shape[item.key()] = r.number(shape, field + ".shape", item.key(), 0.0, -1e6, 1e6);
    }
    const std::vector<std::string> files = r.expand(field + ".body", body);
    for (const std::string& file : files) {
      c.body = file;
      c.name = r.name(characters[i], field, file, body.find_first_of("*?[") != std::string::npos);
      m.characters.push_back(c);
    }
  }
  const Json& clips = list(r, root, "clips");
  for (size_t i = 0; i < clips.size(); ++i) {
    const std::string field = "clips[" + std::to_string(i) + "]";
    r.only(clips[i], field, {"name", "motion", "map", "first", "frames"});
    const std::string motion = r.text(clips[i], field, "motion", "");
    if (motion.empty()) r.fail(field + ".motion", "is required");
    ConvertClip c;
    if (clips[i].contains("map")) c.map = r.existing(field + ".map", r.text(clips[i], field, "map", ""));
    c.first = r.count(clips[i], field, "first");
    c.frames = r.count(clips[i], field, "frames");
    const std::vector<std::string> files = r.expand(field + ".motion", motion);
    for (const std::string& file : files) {
      c.motion = file;
      c.name = r.name(clips[i], field, file, motion.find_first_of("*?[") != std::string::npos);
      m.clips.push_back(c);
    }
  }
  require_unique(r, m.garments, "garments");
  require_unique(r, m.characters, "characters");
  require_unique(r, m.clips, "clips");
  return m;
}

std::vector<ConvertJob> convert_jobs(const ConvertManifest& m) {
  std::vector<ConvertJob> jobs;
  for (const ConvertGarment& g : m.garments)
    for (const ConvertCharacter& c : m.characters)
      for (const ConvertClip& k : m.clips) jobs.push_back({g.name + "-" + c.name + "-" + k.name, &g, &c, &k});
  return jobs;
}

std::string convert_output(const ConvertManifest& m, const ConvertJob& job, const std::string& format) {
  const fs::path dir(m.output);
  if (format == "obj") return (dir / job.name / (job.name + "_####.obj")).string();
  return (dir / (job.name + "." + format)).string();
}

}  // namespace pleat_cli
