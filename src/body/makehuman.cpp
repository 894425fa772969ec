#include "body/makehuman.h"

#include <zlib.h>

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <unordered_map>

#include "core/error.h"

namespace pleat {
namespace {

constexpr double kDecimetre = 0.1;

// ---------------------------------------------------------------- files ----

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path)) fail(PLEAT_ERROR_IO, path + ": cannot open the file");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string read_gzip(const std::string& path) {
  if (std::filesystem::is_directory(path)) fail(PLEAT_ERROR_IO, path + ": is a directory");
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) fail(PLEAT_ERROR_IO, path + ": cannot open the file");
  std::string out;
  std::array<char, 1 << 16> buf;
  int n;
  while ((n = gzread(f, buf.data(), static_cast<unsigned>(buf.size()))) > 0) out.append(buf.data(), n);
  int err = Z_OK;
  const char* message = gzerror(f, &err);
  const std::string what = message ? message : "";
  gzclose(f);
  if (n < 0 || (err != Z_OK && err != Z_STREAM_END))
    fail(PLEAT_ERROR_FORMAT, path + ": corrupt or truncated gzip data (" + what + ")");
  return out;
}

// Splits text into lines (LF or CRLF) and calls fn(line, line_number).
template <typename Fn>
void for_each_line(const std::string& text, Fn fn) {
  size_t at = 0;
  int64_t number = 0;
  while (at < text.size()) {
    size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    size_t stop = end;
    if (stop > at && text[stop - 1] == '\r') --stop;
    fn(std::string_view(text.data() + at, stop - at), ++number);
    at = end + 1;
  }
}

// Parses whitespace-separated numbers from `s` starting at *pos.
template <typename T>
bool next_number(std::string_view s, size_t* pos, T* value) {
  while (*pos < s.size() && (s[*pos] == ' ' || s[*pos] == '\t')) ++*pos;
  if (*pos >= s.size()) return false;
  const char* b = s.data() + *pos;
  const char* e = s.data() + s.size();
  if (*b == '+') ++b;
  auto r = std::from_chars(b, e, *value);
  if (r.ec != std::errc()) return false;
  *pos = static_cast<size_t>(r.ptr - s.data());
  return true;
}

// ----------------------------------------------------------------- JSON ----

// Object members keep their file order: the rig's bone order decides the
// skeleton's (children in file order).
using Json = nlohmann::ordered_json;

Json parse_json(const std::string& path) {
  try {
    return Json::parse(read_text(path));
  } catch (const Json::parse_error& e) {
    fail(PLEAT_ERROR_FORMAT, path + ": not valid JSON: " + e.what());
  }
}

// The member `key` of an object, or null.
const Json* member(const Json& object, const char* key) {
  if (!object.is_object()) return nullptr;
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

bool is_index(const Json& v, int32_t count) {
  if (!v.is_number()) return false;
  const double x = v.get<double>();
  return x >= 0 && x < count && x == std::floor(x);
}

// --------------------------------------------------------------- tokens ----

// Category tokens of target names, in the order makehuman_category_values()
// reports them.
const std::array<const char*, 19> kTokens = {"male",
                                             "female",
                                             "baby",
                                             "child",
                                             "young",
                                             "old",
                                             "african",
                                             "asian",
                                             "caucasian",
                                             "minmuscle",
                                             "averagemuscle",
                                             "maxmuscle",
                                             "minweight",
                                             "averageweight",
                                             "maxweight",
                                             "minheight",
                                             "maxheight",
                                             "idealproportions",
                                             "uncommonproportions"};

std::array<double, kTokens.size()> category_array(const Eigen::VectorXd& beta) {
  const auto params = makehuman_shape_parameters();
  if (beta.size() != kMakeHumanBetaCount)
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         "makehuman: beta has " + std::to_string(beta.size()) + " entries, expected " +
             std::to_string(kMakeHumanBetaCount) +
             " (gender age muscle weight height proportions african asian caucasian)");
  for (int i = 0; i < kMakeHumanBetaCount; ++i)
    if (!std::isfinite(beta[i]) || beta[i] < 0.0 || beta[i] > 1.0)
      fail(PLEAT_ERROR_INVALID_ARGUMENT, "makehuman: beta[" + std::to_string(i) + "] '" + params[i].name +
                                             "' = " + std::to_string(beta[i]) + " is outside [0, 1]");
  const double g = beta[0], a = beta[1], m = beta[2], w = beta[3], h = beta[4], p = beta[5];
  const double ethnic_sum = beta[6] + beta[7] + beta[8];
  if (ethnic_sum <= 0.0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "makehuman: the ethnic values (african, asian, caucasian) sum to 0");
  double baby, child, young, old;
  if (a < 0.5) {
    baby = std::max(0.0, 1.0 - a / 0.1875);
    young = std::max(0.0, (a - 0.1875) / 0.3125);
    child = std::max(0.0, std::min(1.0, a / 0.1875) - young);
    old = 0.0;
  } else {
    baby = child = 0.0;
    old = 2.0 * a - 1.0;
    young = 1.0 - old;
  }
  auto three = [](double x, double* lo, double* mid, double* hi) {
    *hi = std::max(0.0, 2.0 * x - 1.0);
    *lo = std::max(0.0, 1.0 - 2.0 * x);
    *mid = 1.0 - *hi - *lo;
  };
  double mlo, mmid, mhi, wlo, wmid, whi, unused;
  three(m, &mlo, &mmid, &mhi);
  three(w, &wlo, &wmid, &whi);
  double hlo, hhi, plo, phi;
  three(h, &hlo, &unused, &hhi);
  three(p, &plo, &unused, &phi);  // uncommon = lo, ideal = hi
  return {g,
          1.0 - g,
          baby,
          child,
          young,
          old,
          beta[6] / ethnic_sum,
          beta[7] / ethnic_sum,
          beta[8] / ethnic_sum,
          mlo,
          mmid,
          mhi,
          wlo,
          wmid,
          whi,
          hlo,
          hhi,
          phi,
          plo};
}

// ------------------------------------------------------------ shared data --

struct StoredTarget {
  bool loaded = false;
  std::vector<int32_t> index;
  std::vector<float> offset;  // 3 per index, decimetres
};

struct ManifestEntry {
  std::string original;         // path under macrodetails/, e.g. "height/...-maxheight.target"
  int32_t stored = -1;          // index into stored files
  std::vector<int32_t> tokens;  // indices into kTokens
};

// Everything of a body directory that does not depend on the rig.
struct MakeHumanData {
  std::string dir;
  Points3d base;  // decimetres, all vertices
  std::vector<std::string> groups;
  std::vector<std::array<int32_t, 3>> triangles;  // quads split, all groups
  std::vector<int32_t> triangle_group;
  std::vector<ManifestEntry> manifest;
  std::vector<std::string> stored_files;  // relative to targets/macrodetails
  std::mutex mutex;
  std::vector<StoredTarget> stored;

  const StoredTarget& target(int32_t i) {
    std::lock_guard<std::mutex> lock(mutex);
    StoredTarget& t = stored[static_cast<size_t>(i)];
    if (!t.loaded) load_target(i, &t);
    return t;
  }

  void load_target(int32_t i, StoredTarget* t) const {
    const std::string path = dir + "/targets/macrodetails/" + stored_files[static_cast<size_t>(i)];
    const std::string text = read_gzip(path);
    for_each_line(text, [&](std::string_view line, int64_t number) {
      size_t pos = 0;
      while (pos < line.size() && (line[pos] == ' ' || line[pos] == '\t')) ++pos;
      if (pos == line.size() || line[pos] == '#') return;
      int32_t v;
      float d[3];
      if (!next_number(line, &pos, &v) || !next_number(line, &pos, &d[0]) ||
          !next_number(line, &pos, &d[1]) || !next_number(line, &pos, &d[2]))
        fail(PLEAT_ERROR_FORMAT, path + ": line " + std::to_string(number) + " is not 'index dx dy dz'");
      if (v < 0 || v >= base.rows())
        fail(PLEAT_ERROR_FORMAT, path + ": line " + std::to_string(number) + " names vertex " +
                                     std::to_string(v) + " of " + std::to_string(base.rows()));
      if (!std::isfinite(d[0]) || !std::isfinite(d[1]) || !std::isfinite(d[2]))
        fail(PLEAT_ERROR_FORMAT, path + ": line " + std::to_string(number) + " has a non-finite offset");
      t->index.push_back(v);
      t->offset.insert(t->offset.end(), {d[0], d[1], d[2]});
    });
    t->loaded = true;
  }
};

void parse_base_obj(MakeHumanData* d) {
  const std::string path = d->dir + "/base.obj";
  const std::string text = read_text(path);
  std::vector<double> xyz;
  std::map<std::string, int32_t> group_index;
  int32_t group = -1;
  std::vector<std::array<int32_t, 3>> pending;  // faces are checked once all vertices are known
  std::vector<int64_t> pending_line;
  for_each_line(text, [&](std::string_view line, int64_t number) {
    if (line.size() < 2) return;
    const std::string where = path + ": line " + std::to_string(number);
    if (line[0] == 'v' && line[1] == ' ') {
      size_t pos = 1;
      double p[3];
      for (double& c : p)
        if (!next_number(line, &pos, &c) || !std::isfinite(c))
          fail(PLEAT_ERROR_FORMAT, where + ": bad vertex");
      xyz.insert(xyz.end(), {p[0], p[1], p[2]});
    } else if (line[0] == 'g' && line[1] == ' ') {
      std::string name(line.substr(2));
      while (!name.empty() && name.back() == ' ') name.pop_back();
      auto it = group_index.find(name);
      if (it == group_index.end()) {
        it = group_index.emplace(name, static_cast<int32_t>(d->groups.size())).first;
        d->groups.push_back(name);
      }
      group = it->second;
    } else if (line[0] == 'f' && line[1] == ' ') {
      std::vector<int32_t> corners;
      size_t pos = 1;
      while (true) {
        while (pos < line.size() && line[pos] == ' ') ++pos;
        if (pos >= line.size()) break;
        int32_t v;
        auto r = std::from_chars(line.data() + pos, line.data() + line.size(), v);
        if (r.ec != std::errc() || v < 1) fail(PLEAT_ERROR_FORMAT, where + ": bad face corner");
        corners.push_back(v - 1);
        pos = static_cast<size_t>(r.ptr - line.data());
        while (pos < line.size() && line[pos] != ' ') ++pos;  // skip /vt/vn
      }
      if (corners.size() < 3) fail(PLEAT_ERROR_FORMAT, where + ": face with fewer than 3 corners");
      if (group < 0) fail(PLEAT_ERROR_FORMAT, where + ": face before any group");
      for (size_t c = 1; c + 1 < corners.size(); ++c) {  // fan: quads -> (a b c) (a c d)
        d->triangles.push_back({corners[0], corners[c], corners[c + 1]});
        d->triangle_group.push_back(group);
        pending_line.push_back(number);
      }
    }
  });
  const auto n = static_cast<Eigen::Index>(xyz.size() / 3);
  if (n != kMakeHumanVertexCount)
    fail(PLEAT_ERROR_FORMAT, path + ": " + std::to_string(n) + " vertices, the hm08 base mesh has " +
                                 std::to_string(kMakeHumanVertexCount));
  for (size_t t = 0; t < d->triangles.size(); ++t)
    for (int32_t v : d->triangles[t])
      if (v >= n)
        fail(PLEAT_ERROR_FORMAT, path + ": line " + std::to_string(pending_line[t]) + " refers to vertex " +
                                     std::to_string(v + 1) + " of " + std::to_string(n));
  d->base = Eigen::Map<Points3d>(xyz.data(), n, 3);
}

void parse_manifest(MakeHumanData* d) {
  const std::string path = d->dir + "/targets/macrodetails/MANIFEST.tsv";
  const std::string text = read_text(path);
  std::map<std::string, int32_t> stored_index;
  for_each_line(text, [&](std::string_view line, int64_t number) {
    if (line.empty() || line[0] == '#') return;
    const std::string where = path + ": line " + std::to_string(number);
    const size_t tab = line.find('\t');
    if (tab == std::string::npos) fail(PLEAT_ERROR_FORMAT, where + ": expected 'original<TAB>stored...'");
    const size_t tab2 = line.find('\t', tab + 1);
    ManifestEntry e;
    e.original = std::string(line.substr(0, tab));
    const std::string stored(
        line.substr(tab + 1, tab2 == std::string::npos ? std::string::npos : tab2 - tab - 1));
    if (stored.empty() || stored.find("..") != std::string::npos)
      fail(PLEAT_ERROR_FORMAT, where + ": bad stored file name '" + stored + "'");
    auto it = stored_index.find(stored);
    if (it == stored_index.end()) {
      it = stored_index.emplace(stored, static_cast<int32_t>(d->stored_files.size())).first;
      d->stored_files.push_back(stored);
    }
    e.stored = it->second;
    // Tokens of the file name; folder names (height/, proportions/) and
    // "universal" weigh 1.
    std::string name =
        e.original.substr(e.original.rfind('/') == std::string::npos ? 0 : e.original.rfind('/') + 1);
    const std::string suffix = ".target";
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      name.resize(name.size() - suffix.size());
    std::stringstream ss(name);
    std::string token;
    while (std::getline(ss, token, '-')) {
      if (token == "universal") continue;
      size_t k = 0;
      while (k < kTokens.size() && token != kTokens[k]) ++k;
      if (k == kTokens.size())
        fail(PLEAT_ERROR_FORMAT,
             where + ": target '" + e.original + "' has an unknown token '" + token + "'");
      e.tokens.push_back(static_cast<int32_t>(k));
    }
    d->manifest.push_back(std::move(e));
  });
  if (d->manifest.empty()) fail(PLEAT_ERROR_FORMAT, path + ": lists no targets");
  d->stored.resize(d->stored_files.size());
}

std::mutex g_cache_mutex;
std::map<std::string, std::shared_ptr<MakeHumanData>> g_data;
std::map<std::pair<std::string, int>, std::shared_ptr<const MakeHumanModel>> g_models;

std::string canonical_dir(const std::string& dir) {
  std::error_code ec;
  auto p = std::filesystem::weakly_canonical(dir, ec);
  return ec ? dir : p.string();
}

std::shared_ptr<MakeHumanData> shared_data(const std::string& dir) {
  // Called with g_cache_mutex held.
  auto it = g_data.find(dir);
  if (it != g_data.end()) return it->second;
  auto d = std::make_shared<MakeHumanData>();
  d->dir = dir;
  parse_base_obj(d.get());
  parse_manifest(d.get());
  g_data[dir] = d;
  return d;
}

const char* rig_name(MakeHumanRig rig) {
  return rig == MakeHumanRig::cmu_mb ? "cmu_mb" : "default";
}

}  // namespace

// ------------------------------------------------------------- public ------

std::vector<ShapeParameter> makehuman_shape_parameters() {
  const double third = 1.0 / 3.0;
  return {
      {"gender", 0.5, 0.5, 0.0, 1.0, "0 female .. 1 male"},
      {"age", 0.5, 0.5, 0.0, 1.0, "0 = 1 year, 0.1875 = 10, 0.5 = 25, 1 = 90 years"},
      {"muscle", 0.5, 0.5, 0.0, 1.0, "0 minimum .. 0.5 average .. 1 maximum muscle"},
      {"weight", 0.5, 0.5, 0.0, 1.0, "0 minimum .. 0.5 average .. 1 maximum weight"},
      {"height", 0.5, 0.5, 0.0, 1.0, "0 short .. 0.5 average .. 1 tall"},
      {"proportions", 0.5, 0.5, 0.0, 1.0, "0 uncommon .. 0.5 regular .. 1 ideal body proportions"},
      {"african", third, third, 0.0, 1.0, "ethnic mix (the three are renormalised to sum 1)"},
      {"asian", third, third, 0.0, 1.0, "ethnic mix (the three are renormalised to sum 1)"},
      {"caucasian", third, third, 0.0, 1.0, "ethnic mix (the three are renormalised to sum 1)"},
  };
}

Eigen::VectorXd makehuman_default_beta() {
  Eigen::VectorXd b(kMakeHumanBetaCount);
  const auto p = makehuman_shape_parameters();
  for (int i = 0; i < kMakeHumanBetaCount; ++i) b[i] = p[static_cast<size_t>(i)].default_value;
  return b;
}

std::vector<std::pair<std::string, double>> makehuman_category_values(const Eigen::VectorXd& beta) {
  const auto c = category_array(beta);
  std::vector<std::pair<std::string, double>> out;
  for (size_t k = 0; k < kTokens.size(); ++k) out.emplace_back(kTokens[k], c[k]);
  return out;
}

struct MakeHumanModel::Impl {
  std::shared_ptr<MakeHumanData> data;
  std::vector<std::vector<int32_t>> joint_vertices;  // per skeleton joint: its head's vertex group
  Triangles body_triangles;
  Triangles body_and_helper_triangles;
};

MakeHumanModel::MakeHumanModel() : impl_(std::make_unique<Impl>()) {}
MakeHumanModel::~MakeHumanModel() = default;

namespace {

// Reads the rig (.mhskel) into names/parents (parents-first, children in
// file order) and the head vertex group of each bone.
void parse_rig(const std::string& path, int32_t vertex_count, Skeleton* skeleton,
               std::vector<std::vector<int32_t>>* joint_vertices) {
  const Json root = parse_json(path);
  const Json* bones = member(root, "bones");
  const Json* joints = member(root, "joints");
  if (!bones || !bones->is_object() || bones->empty()) fail(PLEAT_ERROR_FORMAT, path + ": no 'bones' object");
  if (!joints || !joints->is_object()) fail(PLEAT_ERROR_FORMAT, path + ": no 'joints' object");
  std::vector<std::pair<std::string, const Json*>> bone_list;
  for (const auto& [name, bone] : bones->items()) bone_list.emplace_back(name, &bone);
  std::map<std::string, size_t> index;
  for (size_t b = 0; b < bone_list.size(); ++b) index[bone_list[b].first] = b;
  std::vector<std::vector<size_t>> children(bone_list.size());
  std::vector<size_t> roots;
  for (size_t b = 0; b < bone_list.size(); ++b) {
    const auto& [name, bone] = bone_list[b];
    const Json* parent = member(*bone, "parent");
    if (!parent || parent->is_null() || (parent->is_string() && parent->get<std::string>().empty())) {
      roots.push_back(b);
      continue;
    }
    if (!parent->is_string() || !index.count(parent->get<std::string>()))
      fail(PLEAT_ERROR_FORMAT, path + ": bone '" + name + "' has an unknown parent");
    children[index[parent->get<std::string>()]].push_back(b);
  }
  if (roots.size() != 1)
    fail(PLEAT_ERROR_FORMAT,
         path + ": the rig has " + std::to_string(roots.size()) + " root bones, expected 1");
  std::vector<size_t> order;
  std::vector<int32_t> parent_of;
  std::vector<std::pair<size_t, int32_t>> stack{{roots[0], -1}};
  while (!stack.empty()) {
    auto [b, parent] = stack.back();
    stack.pop_back();
    order.push_back(b);
    parent_of.push_back(parent);
    const auto me = static_cast<int32_t>(order.size() - 1);
    for (auto it = children[b].rbegin(); it != children[b].rend(); ++it) stack.push_back({*it, me});
  }
  if (order.size() != bone_list.size())
    fail(PLEAT_ERROR_FORMAT, path + ": " + std::to_string(bone_list.size() - order.size()) +
                                 " bones are not connected to the root (a parent cycle)");
  for (size_t j = 0; j < order.size(); ++j) {
    const auto& [name, bone] = bone_list[order[j]];
    skeleton->names.push_back(name);
    skeleton->parents.push_back(parent_of[j]);
    const Json* head = member(*bone, "head");
    if (!head || !head->is_string()) fail(PLEAT_ERROR_FORMAT, path + ": bone '" + name + "' has no 'head'");
    const std::string head_name = head->get<std::string>();
    const Json* group = member(*joints, head_name.c_str());
    if (!group || !group->is_array() || group->empty())
      fail(PLEAT_ERROR_FORMAT,
           path + ": joint '" + head_name + "' of bone '" + name + "' has no vertex list");
    std::vector<int32_t> vertices;
    for (const Json& v : *group) {
      if (!is_index(v, vertex_count))
        fail(PLEAT_ERROR_FORMAT, path + ": joint '" + head_name + "' lists a bad vertex index");
      vertices.push_back(v.get<int32_t>());
    }
    joint_vertices->push_back(std::move(vertices));
  }
  const auto n = static_cast<Eigen::Index>(skeleton->names.size());
  skeleton->rest_translation = Points3d::Zero(n, 3);
  skeleton->rest_rotation.assign(static_cast<size_t>(n), Eigen::Quaterniond::Identity());
}

// Reads {"weights": {bone: [[vertex, weight], ...]}} into per-vertex weights
// (normalised; vertices without any weight go to the root and are reported).
SkinWeights parse_weights(const std::string& path, const Skeleton& skeleton, int32_t vertex_count,
                          std::vector<int32_t>* unweighted) {
  const Json root = parse_json(path);
  const Json* weights = member(root, "weights");
  if (!weights || !weights->is_object()) fail(PLEAT_ERROR_FORMAT, path + ": no 'weights' object");
  std::vector<std::vector<std::pair<int32_t, double>>> per_vertex(static_cast<size_t>(vertex_count));
  for (const auto& [bone, list] : weights->items()) {
    const int32_t j = skeleton.find(bone);
    if (j < 0)
      fail(PLEAT_ERROR_FORMAT, path + ": weights for bone '" + bone + "', which the rig does not have");
    if (!list.is_array()) fail(PLEAT_ERROR_FORMAT, path + ": weights of bone '" + bone + "' are not a list");
    for (size_t k = 0; k < list.size(); ++k) {
      const Json& pair = list[k];
      if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number() || !pair[1].is_number())
        fail(PLEAT_ERROR_FORMAT,
             path + ": bone '" + bone + "' entry " + std::to_string(k) + " is not [vertex, weight]");
      const double v = pair[0].get<double>(), w = pair[1].get<double>();
      if (!is_index(pair[0], vertex_count))
        fail(PLEAT_ERROR_FORMAT, path + ": bone '" + bone + "' entry " + std::to_string(k) +
                                     " names vertex " + std::to_string(v) + " of " +
                                     std::to_string(vertex_count));
      if (!std::isfinite(w) || w < 0)
        fail(PLEAT_ERROR_FORMAT, path + ": bone '" + bone +
                                     "' has a negative or non-finite weight for vertex " +
                                     std::to_string(static_cast<int64_t>(v)));
      if (w > 0) per_vertex[static_cast<size_t>(v)].push_back({j, w});
    }
  }
  SkinWeights out;
  out.joint_count = skeleton.joint_count();
  out.offsets.assign(1, 0);
  for (int32_t v = 0; v < vertex_count; ++v) {
    auto& list = per_vertex[static_cast<size_t>(v)];
    if (list.empty()) {
      unweighted->push_back(v);
      list.push_back({0, 1.0});
    }
    for (const auto& [j, w] : list) {
      out.joints.push_back(j);
      out.weights.push_back(w);
    }
    out.offsets.push_back(static_cast<int32_t>(out.joints.size()));
  }
  normalize_skin_weights(&out, path);
  return out;
}

}  // namespace

std::shared_ptr<const MakeHumanModel> MakeHumanModel::load(const std::string& body_dir, MakeHumanRig rig) {
  const std::string dir = canonical_dir(body_dir);
  std::lock_guard<std::mutex> lock(g_cache_mutex);
  const auto key = std::make_pair(dir, static_cast<int>(rig));
  if (auto it = g_models.find(key); it != g_models.end()) return it->second;
  if (!std::filesystem::is_directory(dir)) fail(PLEAT_ERROR_IO, body_dir + ": no such body data directory");

  auto model = std::shared_ptr<MakeHumanModel>(new MakeHumanModel());
  model->rig_ = rig;
  model->dir_ = dir;
  Impl& impl = *model->impl_;
  impl.data = shared_data(dir);
  const MakeHumanData& d = *impl.data;

  const std::string rig_path =
      dir + (rig == MakeHumanRig::cmu_mb ? "/rigs/cmu_mb.mhskel" : "/rigs/default.mhskel");
  const std::string weights_path =
      dir + (rig == MakeHumanRig::cmu_mb ? "/rigs/mpfb2_weights.cmu_mb.json" : "/rigs/default_weights.mhw");
  parse_rig(rig_path, kMakeHumanVertexCount, &model->skeleton_, &impl.joint_vertices);
  model->all_weights_ =
      parse_weights(weights_path, model->skeleton_, kMakeHumanVertexCount, &model->unweighted_);

  // The body group's triangles (its vertices are 0..13379).
  int32_t body_group = -1;
  for (size_t g = 0; g < d.groups.size(); ++g)
    if (d.groups[g] == "body") body_group = static_cast<int32_t>(g);
  if (body_group < 0) fail(PLEAT_ERROR_FORMAT, dir + "/base.obj: no 'body' group");
  std::vector<int32_t> tri;
  for (size_t t = 0; t < d.triangles.size(); ++t) {
    if (d.triangle_group[t] != body_group) continue;
    for (int32_t v : d.triangles[t]) {
      if (v >= kMakeHumanBodyVertexCount)
        fail(PLEAT_ERROR_FORMAT, dir + "/base.obj: a 'body' face uses vertex " + std::to_string(v) +
                                     ", outside the body range 0.." +
                                     std::to_string(kMakeHumanBodyVertexCount - 1));
      tri.push_back(v);
    }
  }
  impl.body_triangles = Eigen::Map<Triangles>(tri.data(), static_cast<Eigen::Index>(tri.size() / 3), 3);
  tri.clear();
  for (size_t t = 0; t < d.triangles.size(); ++t)
    if (d.groups[static_cast<size_t>(d.triangle_group[t])].rfind("joint-", 0) != 0)
      tri.insert(tri.end(), d.triangles[t].begin(), d.triangles[t].end());
  impl.body_and_helper_triangles =
      Eigen::Map<Triangles>(tri.data(), static_cast<Eigen::Index>(tri.size() / 3), 3);

  // Rest translations of the default shape.
  const Points3d joints = model->joint_positions(model->shaped_vertices(makehuman_default_beta()));
  for (int32_t j = 0; j < model->skeleton_.joint_count(); ++j)
    model->skeleton_.rest_translation.row(j) =
        j == 0 ? joints.row(0) : Eigen::RowVector3d(joints.row(j) - joints.row(model->skeleton_.parents[j]));
  validate_skeleton(model->skeleton_, rig_path);
  g_models[key] = model;
  return model;
}

std::vector<std::pair<std::string, double>> MakeHumanModel::target_weights(
    const Eigen::VectorXd& beta) const {
  const auto c = category_array(beta);
  std::vector<std::pair<std::string, double>> out;
  for (const ManifestEntry& e : impl_->data->manifest) {
    double w = 1.0;
    for (int32_t t : e.tokens) w *= c[static_cast<size_t>(t)];
    if (w != 0.0) out.emplace_back(e.original, w);
  }
  return out;
}

Points3d MakeHumanModel::shaped_vertices(const Eigen::VectorXd& beta) const {
  MakeHumanData& d = *impl_->data;
  const auto c = category_array(beta);
  std::vector<double> stored_weight(d.stored_files.size(), 0.0);
  for (const ManifestEntry& e : d.manifest) {
    double w = 1.0;
    for (int32_t t : e.tokens) w *= c[static_cast<size_t>(t)];
    stored_weight[static_cast<size_t>(e.stored)] += w;
  }
  Points3d x = d.base;
  for (size_t s = 0; s < stored_weight.size(); ++s) {
    const double w = stored_weight[s];
    if (w == 0.0) continue;
    const StoredTarget& t = d.target(static_cast<int32_t>(s));
    for (size_t k = 0; k < t.index.size(); ++k)
      for (int a = 0; a < 3; ++a)
        x(t.index[k], a) += w * static_cast<double>(t.offset[3 * k + static_cast<size_t>(a)]);
  }
  return x * kDecimetre;
}

Points3d MakeHumanModel::joint_positions(const Points3d& shaped) const {
  if (shaped.rows() != kMakeHumanVertexCount)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "makehuman: joint_positions needs all " +
                                           std::to_string(kMakeHumanVertexCount) + " vertices, got " +
                                           std::to_string(shaped.rows()));
  const auto n = static_cast<Eigen::Index>(impl_->joint_vertices.size());
  Points3d j = Points3d::Zero(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& vs = impl_->joint_vertices[static_cast<size_t>(i)];
    for (int32_t v : vs) j.row(i) += shaped.row(v);
    j.row(i) /= static_cast<double>(vs.size());
  }
  return j;
}

Body MakeHumanModel::body(const Eigen::VectorXd& beta) const {
  const Points3d all = shaped_vertices(beta);
  const Points3d joints = joint_positions(all);
  Body b;
  b.source = std::string("makehuman:") + rig_name(rig_);
  b.skeleton = skeleton_;
  for (int32_t j = 0; j < skeleton_.joint_count(); ++j)
    b.skeleton.rest_translation.row(j) =
        j == 0 ? joints.row(0) : Eigen::RowVector3d(joints.row(j) - joints.row(skeleton_.parents[j]));
  b.rest.vertices = all.topRows(kMakeHumanBodyVertexCount);
  b.rest.triangles = impl_->body_triangles;
  b.weights.joint_count = all_weights_.joint_count;
  b.weights.offsets.assign(all_weights_.offsets.begin(),
                           all_weights_.offsets.begin() + kMakeHumanBodyVertexCount + 1);
  const auto nnz = static_cast<size_t>(b.weights.offsets.back());
  b.weights.joints.assign(all_weights_.joints.begin(),
                          all_weights_.joints.begin() + static_cast<std::ptrdiff_t>(nnz));
  b.weights.weights.assign(all_weights_.weights.begin(),
                           all_weights_.weights.begin() + static_cast<std::ptrdiff_t>(nnz));
  b.shape = makehuman_shape_parameters();
  for (int i = 0; i < kMakeHumanBetaCount; ++i) b.shape[static_cast<size_t>(i)].value = beta[i];
  return b;
}

Body MakeHumanModel::body_with_helpers(const Eigen::VectorXd& beta) const {
  Body b = body(beta);
  b.source += "+helpers";
  b.rest.vertices = shaped_vertices(beta);
  b.rest.triangles = impl_->body_and_helper_triangles;
  b.weights = all_weights_;
  return b;
}

std::vector<std::string> MakeHumanModel::group_names() const {
  return impl_->data->groups;
}

std::vector<int32_t> MakeHumanModel::group_vertices(const std::string& group) const {
  const MakeHumanData& d = *impl_->data;
  std::set<int32_t> vs;
  bool found = false;
  for (size_t t = 0; t < d.triangles.size(); ++t)
    if (d.groups[static_cast<size_t>(d.triangle_group[t])] == group) {
      found = true;
      vs.insert(d.triangles[t].begin(), d.triangles[t].end());
    }
  if (!found) fail(PLEAT_ERROR_INVALID_ARGUMENT, "makehuman: base.obj has no group '" + group + "'");
  return {vs.begin(), vs.end()};
}

Triangles MakeHumanModel::group_triangles(const std::string& group) const {
  const MakeHumanData& d = *impl_->data;
  std::vector<int32_t> tri;
  for (size_t t = 0; t < d.triangles.size(); ++t)
    if (d.groups[static_cast<size_t>(d.triangle_group[t])] == group)
      tri.insert(tri.end(), d.triangles[t].begin(), d.triangles[t].end());
  if (tri.empty()) fail(PLEAT_ERROR_INVALID_ARGUMENT, "makehuman: base.obj has no group '" + group + "'");
  return Eigen::Map<Triangles>(tri.data(), static_cast<Eigen::Index>(tri.size() / 3), 3);
}

}  // namespace pleat
