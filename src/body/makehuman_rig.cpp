#include "body/makehuman_rig.h"

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "io/text_file.h"

namespace pleat {
namespace {

// Object members keep their file order: the rig's bone order decides the
// skeleton's (children in file order).
using Json = nlohmann::ordered_json;

Json parse_json(const std::string& path) {
  try {
    return Json::parse(read_text_file(path));
  } catch (const Json::exception& e) {  // parse errors, and numbers out of range (found by fuzzing)
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

}  // namespace

void read_makehuman_rig(const std::string& path, int32_t vertex_count, Skeleton* skeleton,
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

SkinWeights read_makehuman_weights(const std::string& path, const Skeleton& skeleton, int32_t vertex_count,
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

}  // namespace pleat
