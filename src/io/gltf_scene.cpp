#include "io/gltf_scene.h"

#include <assimp/scene.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "core/error.h"
#include "io/gltf_read.h"

namespace pleat {
namespace {

// Real rigs nest a few dozen nodes deep; the importers walk the tree by
// recursion, so a crafted chain must not reach them.
constexpr size_t kMaxNodeDepth = 1000;
// The identity node above the file's roots.
constexpr const char* kRootName = "(glTF scene)";
// aiString holds at most 1,023 bytes and silently drops a longer name.
constexpr size_t kMaxNameBytes = 1000;

aiMatrix4x4 column_major(const double* m) {
  aiMatrix4x4 out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[r][c] = static_cast<ai_real>(m[c * 4 + r]);
  return out;
}

aiMatrix4x4 local_transform(const tinygltf::Node& node, const std::string& path, const std::string& field) {
  const auto sized = [&](const std::vector<double>& v, size_t n, const char* what) {
    if (!v.empty() && v.size() != n)
      fail_gltf(path, field + "." + what + " has " + std::to_string(v.size()) + " numbers, not " +
                          std::to_string(n));
    return !v.empty();
  };
  if (sized(node.matrix, 16, "matrix")) return column_major(node.matrix.data());
  aiVector3D t(0, 0, 0), s(1, 1, 1);
  aiQuaternion r;
  if (sized(node.translation, 3, "translation"))
    t = aiVector3D(static_cast<ai_real>(node.translation[0]), static_cast<ai_real>(node.translation[1]),
                   static_cast<ai_real>(node.translation[2]));
  if (sized(node.rotation, 4, "rotation"))
    r = aiQuaternion(static_cast<ai_real>(node.rotation[3]), static_cast<ai_real>(node.rotation[0]),
                     static_cast<ai_real>(node.rotation[1]), static_cast<ai_real>(node.rotation[2]));
  if (sized(node.scale, 3, "scale"))
    s = aiVector3D(static_cast<ai_real>(node.scale[0]), static_cast<ai_real>(node.scale[1]),
                   static_cast<ai_real>(node.scale[2]));
  return aiMatrix4x4(s, r, t);
}

// assimp's destructors free an array only when its count is non-zero, so an
// empty list is null.
template <class T>
T* new_array(const std::vector<T>& values) {
  if (values.empty()) return nullptr;
  T* out = new T[values.size()];
  std::copy(values.begin(), values.end(), out);
  return out;
}

class SceneBuilder {
 public:
  SceneBuilder(const std::string& path, const tinygltf::Model& model) : path_(path), model_(model) {}

  std::unique_ptr<aiScene> build() {
    auto scene = std::make_unique<aiScene>();
    scene_ = scene.get();
    scene->mRootNode = new aiNode(kRootName);
    names_.insert(kRootName);  // a node of the file named so is renamed
    build_nodes(roots());
    for (size_t a = 0; a < model_.animations.size(); ++a) add_animation(a);
    scene->mNumMeshes = static_cast<unsigned>(meshes_.size());
    scene->mMeshes = new_array(meshes_);
    meshes_.clear();
    scene->mNumAnimations = static_cast<unsigned>(animations_.size());
    scene->mAnimations = new_array(animations_);
    animations_.clear();
    return scene;
  }

  ~SceneBuilder() {
    for (aiMesh* m : meshes_) delete m;
    for (aiAnimation* a : animations_) delete a;
  }

 private:
  std::string node_field(size_t n) const { return "nodes[" + std::to_string(n) + "]"; }

  std::vector<int> roots() const {
    if (!model_.scenes.empty()) {
      const int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      return model_.scenes[gltf_index(s, model_.scenes.size(), path_, "scene", "scene")].nodes;
    }
    std::vector<bool> child(model_.nodes.size(), false);
    for (const tinygltf::Node& n : model_.nodes)
      for (int c : n.children)
        if (c >= 0 && static_cast<size_t>(c) < child.size()) child[static_cast<size_t>(c)] = true;
    std::vector<int> out;
    for (size_t n = 0; n < child.size(); ++n)
      if (!child[n]) out.push_back(static_cast<int>(n));
    return out;
  }

  // Every node reachable from the roots, each once, as an aiNode under the
  // scene's root; then each node's meshes.
  void build_nodes(const std::vector<int>& roots) {
    node_of_.assign(model_.nodes.size(), nullptr);
    std::vector<std::unique_ptr<aiNode>> pending(model_.nodes.size());  // made, not yet in the tree
    struct Visit {
      int index;
      aiNode* parent;
      size_t depth;
      std::string field;  // where the index was read
    };
    std::vector<std::pair<size_t, aiNode*>> order;  // glTF node and its parent, parents first
    std::vector<Visit> stack;
    for (size_t r = roots.size(); r-- > 0;)
      stack.push_back({roots[r], scene_->mRootNode, 1, "scene.nodes[" + std::to_string(r) + "]"});
    while (!stack.empty()) {
      const Visit visit = std::move(stack.back());
      stack.pop_back();
      const size_t n = gltf_index(visit.index, model_.nodes.size(), path_, visit.field, "node");
      if (node_of_[n])
        fail_gltf(path_, visit.field + " reaches " + node_field(n) +
                             " a second time (glTF nodes form trees: one parent each)");
      if (visit.depth > kMaxNodeDepth)
        fail_gltf(path_, node_field(n) + " lies deeper than " + std::to_string(kMaxNodeDepth) + " levels");
      const tinygltf::Node& node = model_.nodes[n];
      pending[n] = std::make_unique<aiNode>(unique_name(node.name, n));
      node_of_[n] = pending[n].get();
      node_of_[n]->mTransformation = local_transform(node, path_, node_field(n));
      order.push_back({n, visit.parent});
      for (size_t c = node.children.size(); c-- > 0;)
        stack.push_back({node.children[c], node_of_[n], visit.depth + 1,
                         node_field(n) + ".children[" + std::to_string(c) + "]"});
    }
    // Children arrays sized once each (aiNode::addChildren copies its array
    // on every call); from here the tree owns its nodes.
    for (const auto& [n, parent] : order) pending[n].release();
    std::map<aiNode*, std::vector<aiNode*>> children;
    for (const auto& [n, parent] : order) children[parent].push_back(node_of_[n]);
    for (auto& [parent, list] : children) {
      parent->mChildren = new_array(list);
      parent->mNumChildren = static_cast<unsigned>(list.size());
      for (aiNode* c : list) c->mParent = parent;
    }
    for (const auto& [n, parent] : order) add_meshes(n);
  }

  std::string unique_name(const std::string& given, size_t index) {
    std::string name = given.substr(0, std::min(given.find('\0'), kMaxNameBytes));
    if (name.empty()) name = "node" + std::to_string(index);
    if (!names_.insert(name).second) name += "#" + std::to_string(index);
    names_.insert(name);
    return name;
  }

  void add_meshes(size_t n) {
    const tinygltf::Node& node = model_.nodes[n];
    if (node.mesh < 0) return;
    const std::string field = node_field(n);
    const size_t m = gltf_index(node.mesh, model_.meshes.size(), path_, field + ".mesh", "mesh");
    // Nodes that show one mesh with one skin share its aiMeshes, as assimp's
    // importer does (a few bytes of JSON must not copy a large mesh per node).
    const auto [shared, first] = instances_.insert({{m, node.skin}, {}});
    std::vector<unsigned>& mine = shared->second;
    for (size_t p = 0; first && p < model_.meshes[m].primitives.size(); ++p) {
      aiMesh* mesh = primitive_mesh(m, p);
      if (!mesh) continue;
      meshes_.push_back(mesh);
      if (node.skin >= 0) add_bones(n, mesh, m, p);
      mine.push_back(static_cast<unsigned>(meshes_.size() - 1));
    }
    aiNode* ai = node_of_[n];
    ai->mNumMeshes = static_cast<unsigned>(mine.size());
    ai->mMeshes = new_array(mine);
  }

  std::string primitive_field(size_t m, size_t p) const {
    return "meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "]";
  }

  // Triangles of one primitive, or null for points and lines.
  aiMesh* primitive_mesh(size_t m, size_t p) {
    const tinygltf::Primitive& primitive = model_.meshes[m].primitives[p];
    const std::string field = primitive_field(m, p);
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode < TINYGLTF_MODE_TRIANGLES) return nullptr;
    if (mode > TINYGLTF_MODE_TRIANGLE_FAN)
      fail_gltf(path_, field + ".mode " + std::to_string(mode) + " is not a glTF primitive mode");
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) fail_gltf(path_, field + " has no POSITION");
    const std::vector<double> xyz = read_gltf_accessor(
        model_, position->second, 3, {TINYGLTF_COMPONENT_TYPE_FLOAT}, path_, field + " POSITION");
    const size_t vertex_count = xyz.size() / 3;
    std::vector<unsigned> index;
    if (primitive.indices >= 0) {
      const std::vector<double> read =
          read_gltf_accessor(model_, primitive.indices, 1,
                             {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                             path_, field + " indices");
      for (size_t i = 0; i < read.size(); ++i) {
        if (read[i] >= static_cast<double>(vertex_count))
          fail_gltf(path_, field + " index " + std::to_string(i) + " is " +
                               std::to_string(static_cast<uint64_t>(read[i])) + ", of " +
                               std::to_string(vertex_count) + " vertices");
        index.push_back(static_cast<unsigned>(read[i]));
      }
    } else {
      for (size_t v = 0; v < vertex_count; ++v) index.push_back(static_cast<unsigned>(v));
    }
    std::vector<std::array<unsigned, 3>> triangles;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      for (size_t i = 0; i + 2 < index.size(); i += 3)
        triangles.push_back({index[i], index[i + 1], index[i + 2]});
    } else {
      for (size_t i = 0; i + 2 < index.size(); ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_FAN)
          triangles.push_back({index[0], index[i + 1], index[i + 2]});
        else if (i % 2 == 0)
          triangles.push_back({index[i], index[i + 1], index[i + 2]});
        else
          triangles.push_back({index[i + 1], index[i], index[i + 2]});
      }
    }
    if (triangles.empty()) return nullptr;

    auto mesh = std::make_unique<aiMesh>();
    mesh->mName = aiString(model_.meshes[m].name.substr(0, kMaxNameBytes));
    mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    mesh->mNumVertices = static_cast<unsigned>(vertex_count);
    mesh->mVertices = new aiVector3D[vertex_count];
    for (size_t v = 0; v < vertex_count; ++v)
      mesh->mVertices[v] = aiVector3D(static_cast<ai_real>(xyz[3 * v]), static_cast<ai_real>(xyz[3 * v + 1]),
                                      static_cast<ai_real>(xyz[3 * v + 2]));
    mesh->mNumFaces = static_cast<unsigned>(triangles.size());
    mesh->mFaces = new aiFace[triangles.size()];
    for (size_t f = 0; f < triangles.size(); ++f) {
      mesh->mFaces[f].mNumIndices = 3;
      mesh->mFaces[f].mIndices = new unsigned[3]{triangles[f][0], triangles[f][1], triangles[f][2]};
    }
    return mesh.release();
  }

  // One bone per joint of node n's skin (a joint no vertex weighs has no
  // weights), as assimp's importer makes them.
  void add_bones(size_t n, aiMesh* mesh, size_t m, size_t p) {
    const std::string node = node_field(n);
    const size_t s = gltf_index(model_.nodes[n].skin, model_.skins.size(), path_, node + ".skin", "skin");
    const tinygltf::Skin& skin = model_.skins[s];
    const std::string skin_field = "skins[" + std::to_string(s) + "]";
    const size_t joint_count = skin.joints.size();
    if (joint_count == 0) fail_gltf(path_, skin_field + " has no joints");
    std::vector<aiNode*> joint_node(joint_count);
    for (size_t k = 0; k < joint_count; ++k) {
      const std::string field = skin_field + ".joints[" + std::to_string(k) + "]";
      joint_node[k] = node_of_[gltf_index(skin.joints[k], model_.nodes.size(), path_, field, "node")];
      if (!joint_node[k]) fail_gltf(path_, field + " names a node that is not in the scene");
    }
    std::vector<double> inverse_bind(16 * joint_count, 0.0);
    for (size_t k = 0; k < joint_count; ++k)
      for (int d = 0; d < 4; ++d) inverse_bind[16 * k + 5 * static_cast<size_t>(d)] = 1.0;
    if (skin.inverseBindMatrices >= 0) {
      const std::vector<double> read =
          read_gltf_accessor(model_, skin.inverseBindMatrices, 16, {TINYGLTF_COMPONENT_TYPE_FLOAT}, path_,
                             skin_field + ".inverseBindMatrices");
      if (read.size() < inverse_bind.size())
        fail_gltf(path_, skin_field + ".inverseBindMatrices holds " + std::to_string(read.size() / 16) +
                             " matrices for " + std::to_string(joint_count) + " joints");
      std::copy(read.begin(), read.begin() + static_cast<std::ptrdiff_t>(inverse_bind.size()),
                inverse_bind.begin());
    }

    std::vector<std::vector<aiVertexWeight>> weights(joint_count);
    const tinygltf::Primitive& primitive = model_.meshes[m].primitives[p];
    for (int set = 0;; ++set) {
      const auto joints = primitive.attributes.find("JOINTS_" + std::to_string(set));
      const auto amounts = primitive.attributes.find("WEIGHTS_" + std::to_string(set));
      if (joints == primitive.attributes.end() || amounts == primitive.attributes.end()) break;
      const std::string field = primitive_field(m, p) + " JOINTS_" + std::to_string(set);
      const std::vector<double> j = read_gltf_accessor(
          model_, joints->second, 4,
          {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT}, path_, field);
      const std::vector<double> w =
          read_gltf_accessor(model_, amounts->second, 4,
                             {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                             path_, primitive_field(m, p) + " WEIGHTS_" + std::to_string(set));
      if (j.size() != 4 * size_t{mesh->mNumVertices} || w.size() != j.size())
        fail_gltf(path_, field + " and its weights hold " + std::to_string(j.size() / 4) + " and " +
                             std::to_string(w.size() / 4) + " vertices, POSITION " +
                             std::to_string(mesh->mNumVertices));
      for (size_t i = 0; i < j.size(); ++i) {
        if (w[i] == 0.0) continue;
        if (j[i] >= static_cast<double>(joint_count))
          fail_gltf(path_, field + " vertex " + std::to_string(i / 4) + " names joint " +
                               std::to_string(static_cast<int64_t>(j[i])) + " of " +
                               std::to_string(joint_count));
        weights[static_cast<size_t>(j[i])].emplace_back(static_cast<unsigned>(i / 4),
                                                        static_cast<ai_real>(w[i]));
      }
    }

    mesh->mNumBones = static_cast<unsigned>(joint_count);
    mesh->mBones = new aiBone*[joint_count]();
    for (size_t k = 0; k < joint_count; ++k) {
      aiBone* bone = mesh->mBones[k] = new aiBone();
      bone->mName = joint_node[k]->mName;
      bone->mOffsetMatrix = column_major(&inverse_bind[16 * k]);
      bone->mNumWeights = static_cast<unsigned>(weights[k].size());
      bone->mWeights = new_array(weights[k]);
    }
  }

  template <class Key, class Value>
  Key* keys(const std::vector<double>& times, const std::vector<double>& values, int width, bool cubic,
            unsigned* count, Value (*make)(const double*)) {
    const size_t per_key = static_cast<size_t>(width) * (cubic ? 3 : 1);
    auto* out = new Key[times.size()];
    for (size_t k = 0; k < times.size(); ++k) {
      out[k].mTime = times[k];
      out[k].mValue = make(&values[k * per_key + (cubic ? static_cast<size_t>(width) : 0)]);
    }
    *count = static_cast<unsigned>(times.size());
    return out;
  }

  void add_animation(size_t a) {
    const tinygltf::Animation& animation = model_.animations[a];
    auto anim = std::make_unique<aiAnimation>();
    anim->mName = aiString(animation.name.substr(0, kMaxNameBytes));
    anim->mTicksPerSecond = 1.0;
    std::map<size_t, std::unique_ptr<aiNodeAnim>> channels;  // by glTF node
    for (size_t c = 0; c < animation.channels.size(); ++c) {
      const tinygltf::AnimationChannel& channel = animation.channels[c];
      const std::string field = "animations[" + std::to_string(a) + "].channels[" + std::to_string(c) + "]";
      const bool rotation = channel.target_path == "rotation";
      if (!rotation && channel.target_path != "translation") continue;
      const size_t n = gltf_index(channel.target_node, model_.nodes.size(), path_, field + " target", "node");
      if (!node_of_[n]) continue;  // a node outside the scene moves nothing
      const tinygltf::AnimationSampler& sampler =
          animation.samplers[gltf_index(channel.sampler, animation.samplers.size(), path_, field, "sampler")];
      const std::vector<double> times = read_gltf_accessor(
          model_, sampler.input, 1, {TINYGLTF_COMPONENT_TYPE_FLOAT}, path_, field + " input");
      for (size_t k = 0; k < times.size(); ++k)
        if (!std::isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1])))
          fail_gltf(path_,
                    field + " key " + std::to_string(k) + " is not a time later than the key before it");
      const int width = rotation ? 4 : 3;
      const std::vector<double> values = read_gltf_accessor(
          model_, sampler.output, width,
          rotation ? std::initializer_list<int>{TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
                                                TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                                TINYGLTF_COMPONENT_TYPE_SHORT,
                                                TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT}
                   : std::initializer_list<int>{TINYGLTF_COMPONENT_TYPE_FLOAT},
          path_, field + " output");
      const bool cubic = sampler.interpolation == "CUBICSPLINE";
      if (values.size() != times.size() * static_cast<size_t>(width) * (cubic ? 3 : 1))
        fail_gltf(path_, field + " output holds " +
                             std::to_string(values.size() / static_cast<size_t>(width)) + " values for " +
                             std::to_string(times.size()) + " keys");
      if (times.empty()) continue;
      anim->mDuration = std::max(anim->mDuration, times.back());
      std::unique_ptr<aiNodeAnim>& ch = channels[n];
      if (!ch) {
        ch = std::make_unique<aiNodeAnim>();
        ch->mNodeName = node_of_[n]->mName;
      }
      if (rotation) {
        delete[] ch->mRotationKeys;
        ch->mRotationKeys = nullptr;
        ch->mRotationKeys = keys<aiQuatKey>(
            times, values, 4, cubic, &ch->mNumRotationKeys, +[](const double* q) {
              return aiQuaternion(static_cast<ai_real>(q[3]), static_cast<ai_real>(q[0]),
                                  static_cast<ai_real>(q[1]), static_cast<ai_real>(q[2]));
            });
      } else {
        delete[] ch->mPositionKeys;
        ch->mPositionKeys = nullptr;
        ch->mPositionKeys = keys<aiVectorKey>(
            times, values, 3, cubic, &ch->mNumPositionKeys, +[](const double* t) {
              return aiVector3D(static_cast<ai_real>(t[0]), static_cast<ai_real>(t[1]),
                                static_cast<ai_real>(t[2]));
            });
      }
    }
    anim->mNumChannels = static_cast<unsigned>(channels.size());
    std::vector<aiNodeAnim*> list;
    for (auto& [n, ch] : channels) list.push_back(ch.get());
    anim->mChannels = new_array(list);
    for (auto& [n, ch] : channels) ch.release();
    animations_.push_back(anim.release());
  }

  const std::string& path_;
  const tinygltf::Model& model_;
  aiScene* scene_ = nullptr;
  std::vector<aiNode*> node_of_;  // by glTF node; null where not in the scene
  std::set<std::string> names_;
  std::map<std::pair<size_t, int>, std::vector<unsigned>> instances_;  // (mesh, skin) -> its aiMeshes
  std::vector<aiMesh*> meshes_;
  std::vector<aiAnimation*> animations_;
};

}  // namespace

std::unique_ptr<aiScene> read_gltf_scene(const std::string& path) {
  const tinygltf::Model model = read_gltf_model(path);
  return SceneBuilder(path, model).build();
}

}  // namespace pleat
