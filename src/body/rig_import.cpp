#include "body/rig_import.h"

#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "core/error.h"
#include "io/scene_file.h"

namespace pleat {
namespace {

Eigen::Matrix4d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) e(r, c) = static_cast<double>(m[r][c]);
  return e;
}

Eigen::Quaterniond to_eigen(const aiQuaternion& q) {
  return Eigen::Quaterniond(static_cast<double>(q.w), static_cast<double>(q.x), static_cast<double>(q.y),
                            static_cast<double>(q.z));
}

Eigen::Vector3d to_eigen(const aiVector3D& v) {
  return Eigen::Vector3d(static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z));
}

// Rotation part of an affine matrix with scale removed (polar decomposition).
Eigen::Quaterniond rigid_rotation(const Eigen::Matrix4d& m) {
  Eigen::Affine3d a(m);
  Eigen::Matrix3d rotation, scaling;
  a.computeRotationScaling(&rotation, &scaling);
  return Eigen::Quaterniond(rotation).normalized();
}

Eigen::Matrix4d global_of(const aiNode* node) {
  Eigen::Matrix4d g = Eigen::Matrix4d::Identity();
  for (const aiNode* n = node; n; n = n->mParent) g = to_eigen(n->mTransformation) * g;
  return g;
}

struct Instance {
  const aiMesh* mesh;
  const aiNode* node;
};

void collect_instances(const aiScene* scene, const aiNode* node, std::vector<Instance>* out) {
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[i]];
    if (mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) out->push_back({mesh, node});
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) collect_instances(scene, node->mChildren[c], out);
}

template <typename Key>
size_t key_interval(const Key* keys, unsigned count, double tick, double* alpha) {
  // Index i with keys[i].mTime <= tick < keys[i+1].mTime, clamped; alpha in [0,1].
  if (count == 1 || tick <= keys[0].mTime) {
    *alpha = 0.0;
    return 0;
  }
  if (tick >= keys[count - 1].mTime) {
    *alpha = 1.0;
    return count - 2;
  }
  size_t lo = 0, hi = count - 1;
  while (hi - lo > 1) {
    const size_t mid = (lo + hi) / 2;
    (keys[mid].mTime <= tick ? lo : hi) = mid;
  }
  const double span = keys[hi].mTime - keys[lo].mTime;
  *alpha = span > 0.0 ? (tick - keys[lo].mTime) / span : 0.0;
  return lo;
}

Eigen::Quaterniond sample_rotation(const aiNodeAnim* ch, double tick) {
  double a;
  const size_t i = key_interval(ch->mRotationKeys, ch->mNumRotationKeys, tick, &a);
  const Eigen::Quaterniond q0 = to_eigen(ch->mRotationKeys[i].mValue).normalized();
  if (ch->mNumRotationKeys == 1) return q0;
  const Eigen::Quaterniond q1 = to_eigen(ch->mRotationKeys[i + 1].mValue).normalized();
  return q0.slerp(a, q1).normalized();
}

Eigen::Vector3d sample_position(const aiNodeAnim* ch, double tick) {
  double a;
  const size_t i = key_interval(ch->mPositionKeys, ch->mNumPositionKeys, tick, &a);
  const Eigen::Vector3d p0 = to_eigen(ch->mPositionKeys[i].mValue);
  if (ch->mNumPositionKeys == 1) return p0;
  return (1.0 - a) * p0 + a * to_eigen(ch->mPositionKeys[i + 1].mValue);
}

using Matrices = std::vector<Eigen::Matrix4d, Eigen::aligned_allocator<Eigen::Matrix4d>>;

// The skinned meshes' bone nodes, their lowest common ancestor (the root
// joint) and every node between: the joints, parents first.
struct Joints {
  std::vector<const aiNode*> nodes;
  std::vector<int32_t> parents;
  std::map<const aiNode*, int32_t> index;
  std::map<std::string, const aiNode*> bone_node;  // by bone name
};

Joints find_joints(const aiScene* scene, const std::vector<Instance>& instances, const std::string& path) {
  Joints out;
  std::vector<const aiNode*> bone_nodes;
  for (const Instance& in : instances)
    for (unsigned b = 0; b < in.mesh->mNumBones; ++b) {
      const std::string name = in.mesh->mBones[b]->mName.C_Str();
      if (out.bone_node.count(name)) continue;
      const aiNode* node = scene->mRootNode->FindNode(in.mesh->mBones[b]->mName);
      if (!node) fail(PLEAT_ERROR_FORMAT, path + ": bone '" + name + "' has no node in the hierarchy");
      out.bone_node[name] = node;
      bone_nodes.push_back(node);
    }
  if (bone_nodes.empty())
    fail(PLEAT_ERROR_FORMAT, path + ": the meshes carry no bones (not a skinned character)");
  auto ancestry = [](const aiNode* n) {
    std::vector<const aiNode*> chain;
    for (; n; n = n->mParent) chain.push_back(n);
    std::reverse(chain.begin(), chain.end());
    return chain;  // scene root first
  };
  std::vector<const aiNode*> common = ancestry(bone_nodes[0]);
  for (const aiNode* b : bone_nodes) {
    const auto chain = ancestry(b);
    size_t k = 0;
    while (k < common.size() && k < chain.size() && common[k] == chain[k]) ++k;
    common.resize(k);
  }
  const aiNode* root = common.back();
  std::set<const aiNode*> joint_set;
  for (const aiNode* b : bone_nodes)
    for (const aiNode* n = b; n; n = n->mParent) {
      joint_set.insert(n);
      if (n == root) break;
    }
  std::vector<std::pair<const aiNode*, int32_t>> stack{{root, -1}};
  while (!stack.empty()) {
    auto [n, parent] = stack.back();
    stack.pop_back();
    out.nodes.push_back(n);
    out.parents.push_back(parent);
    const auto me = static_cast<int32_t>(out.nodes.size() - 1);
    for (unsigned c = n->mNumChildren; c-- > 0;)
      if (joint_set.count(n->mChildren[c])) stack.push_back({n->mChildren[c], me});
  }
  for (size_t j = 0; j < out.nodes.size(); ++j) out.index[out.nodes[j]] = static_cast<int32_t>(j);
  return out;
}

// The rigid skeleton of the node hierarchy's rest pose; `world` receives each
// joint's rest world transform (units applied).
Skeleton rest_skeleton(const Joints& joints, const Eigen::Matrix4d& unit, const std::string& path,
                       Matrices* world) {
  const auto n = static_cast<int32_t>(joints.nodes.size());
  world->resize(static_cast<size_t>(n));
  Skeleton s;
  s.rest_translation.resize(n, 3);
  Quaternions global_rotation(static_cast<size_t>(n));
  for (int32_t j = 0; j < n; ++j) {
    const aiNode* node = joints.nodes[static_cast<size_t>(j)];
    Eigen::Matrix4d& w = (*world)[static_cast<size_t>(j)];
    w = unit * global_of(node);
    if (!w.allFinite())
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           path + ": node '" + std::string(node->mName.C_Str()) + "' has a non-finite transform");
    global_rotation[j] = rigid_rotation(w);
    s.names.push_back(node->mName.C_Str());
    s.parents.push_back(joints.parents[static_cast<size_t>(j)]);
    const Eigen::Vector3d p = w.block<3, 1>(0, 3);
    if (j == 0) {
      s.rest_translation.row(0) = p.transpose();
      s.rest_rotation.push_back(global_rotation[0]);
    } else {
      const int32_t q = joints.parents[static_cast<size_t>(j)];
      const Eigen::Quaterniond inv = global_rotation[q].conjugate();
      s.rest_translation.row(j) =
          (inv * (p - Eigen::Vector3d((*world)[static_cast<size_t>(q)].block<3, 1>(0, 3)))).transpose();
      s.rest_rotation.push_back((inv * global_rotation[j]).normalized());
    }
  }
  validate_skeleton(s, path);
  return s;
}

// Appends one mesh instance to the rest mesh (vertices in their bind pose,
// from the bones' offset matrices) and its weights to `w`. Vertices no bone
// weighs follow the mesh node's nearest joint ancestor rigidly.
void add_rest_mesh(const Instance& in, const Joints& joints, const Matrices& world,
                   const Eigen::Matrix4d& unit, const std::string& path, std::vector<double>* xyz,
                   std::vector<int32_t>* tri, SkinWeights* w, std::vector<int32_t>* unweighted) {
  const aiMesh* mesh = in.mesh;
  const auto base = static_cast<int32_t>(xyz->size() / 3);
  std::vector<std::vector<std::pair<int32_t, double>>> influences(mesh->mNumVertices);
  Matrices skin(mesh->mNumBones);
  std::vector<int32_t> joint_of_bone(mesh->mNumBones);
  for (unsigned b = 0; b < mesh->mNumBones; ++b) {
    const aiBone* bone = mesh->mBones[b];
    const int32_t j = joints.index.at(joints.bone_node.at(bone->mName.C_Str()));
    joint_of_bone[b] = j;
    skin[b] = world[static_cast<size_t>(j)] * to_eigen(bone->mOffsetMatrix);
    for (unsigned k = 0; k < bone->mNumWeights; ++k) {
      const aiVertexWeight& vw = bone->mWeights[k];
      if (vw.mVertexId >= mesh->mNumVertices)
        fail(PLEAT_ERROR_FORMAT, path + ": bone '" + std::string(bone->mName.C_Str()) + "' weighs vertex " +
                                     std::to_string(vw.mVertexId) + " of " +
                                     std::to_string(mesh->mNumVertices));
      if (!std::isfinite(vw.mWeight) || vw.mWeight < 0.0f)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, path + ": bone '" + std::string(bone->mName.C_Str()) +
                                               "' has a bad weight for vertex " +
                                               std::to_string(vw.mVertexId));
      if (vw.mWeight > 0.0f) influences[vw.mVertexId].push_back({static_cast<int32_t>(b), vw.mWeight});
    }
  }
  int32_t rigid = 0;
  for (const aiNode* a = in.node; a; a = a->mParent)
    if (joints.index.count(a)) {
      rigid = joints.index.at(a);
      break;
    }
  const Eigen::Matrix4d mesh_world = unit * global_of(in.node);
  for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
    const Eigen::Vector4d p(mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z, 1.0);
    if (!p.allFinite())
      fail(PLEAT_ERROR_INVALID_ARGUMENT, path + ": mesh '" + std::string(mesh->mName.C_Str()) + "' vertex " +
                                             std::to_string(v) + " is not finite");
    const auto& inf = influences[v];
    double total = 0.0;
    for (const auto& [b, x] : inf) total += x;
    Eigen::Vector4d rest = Eigen::Vector4d::Zero();
    if (total > 0.0) {
      for (const auto& [b, x] : inf) {
        rest += (x / total) * (skin[static_cast<size_t>(b)] * p);
        w->joints.push_back(joint_of_bone[static_cast<size_t>(b)]);
        w->weights.push_back(x);
      }
    } else {
      rest = mesh_world * p;
      unweighted->push_back(base + static_cast<int32_t>(v));
      w->joints.push_back(rigid);
      w->weights.push_back(1.0);
    }
    w->offsets.push_back(static_cast<int32_t>(w->joints.size()));
    xyz->insert(xyz->end(), {rest.x(), rest.y(), rest.z()});
  }
  for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
    const aiFace& face = mesh->mFaces[f];
    if (face.mNumIndices != 3) continue;
    for (int c = 0; c < 3; ++c) tri->push_back(base + static_cast<int32_t>(face.mIndices[c]));
  }
}

// The channels of `anim` per joint (null where a joint has none) and every
// key time, checked finite; channels of nodes that are not joints are listed.
std::vector<const aiNodeAnim*> joint_channels(const aiAnimation* anim, const Skeleton& s,
                                              const std::string& where, std::vector<double>* times,
                                              std::vector<std::string>* ignored) {
  std::vector<const aiNodeAnim*> channel(static_cast<size_t>(s.joint_count()), nullptr);
  for (unsigned c = 0; c < anim->mNumChannels; ++c) {
    const aiNodeAnim* ch = anim->mChannels[c];
    const int32_t j = s.find(ch->mNodeName.C_Str());
    if (j < 0) {
      ignored->push_back(ch->mNodeName.C_Str());
      continue;
    }
    channel[static_cast<size_t>(j)] = ch;
    for (unsigned k = 0; k < ch->mNumRotationKeys; ++k) {
      if (!std::isfinite(ch->mRotationKeys[k].mTime) ||
          !to_eigen(ch->mRotationKeys[k].mValue).coeffs().allFinite() ||
          to_eigen(ch->mRotationKeys[k].mValue).norm() < 1e-12)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, where + ": joint '" + s.names[static_cast<size_t>(j)] +
                                               "' rotation key " + std::to_string(k) +
                                               " is not a finite rotation");
      times->push_back(ch->mRotationKeys[k].mTime);
    }
    for (unsigned k = 0; k < (j == 0 ? ch->mNumPositionKeys : 0u); ++k) {
      if (!std::isfinite(ch->mPositionKeys[k].mTime) || !to_eigen(ch->mPositionKeys[k].mValue).allFinite())
        fail(PLEAT_ERROR_INVALID_ARGUMENT,
             where + ": root position key " + std::to_string(k) + " is not finite");
      times->push_back(ch->mPositionKeys[k].mTime);
    }
  }
  return channel;
}

// The clip's frame rate when the caller gives none: the densest key spacing,
// kept within 1..240 fps and snapped to a whole rate when within 1e-3. (Keys
// more than a second apart are sampled at 1 fps; a fuzzer found that keys
// 1e38 ticks apart snapped the rate to 0 and every sample to NaN.)
double key_rate(std::vector<double> times, double ticks_per_second) {
  std::sort(times.begin(), times.end());
  double step = 0.0;
  for (size_t k = 1; k < times.size(); ++k) {
    const double d = (times[k] - times[k - 1]) / ticks_per_second;
    if (d > 1e-6 && (step == 0.0 || d < step)) step = d;
  }
  double rate = step > 0.0 ? std::clamp(1.0 / step, 1.0, 240.0) : 30.0;
  if (std::abs(rate - std::round(rate)) < 1e-3) rate = std::round(rate);
  return rate;
}

// One animation sampled at the clip's rate on the rig's skeleton. `above`:
// the world transform of the root joint's parent, which the root's channel
// is relative to.
ImportedClip import_clip(const aiAnimation* anim, unsigned index, const Skeleton& s,
                         const Eigen::Matrix4d& above, double frame_rate, const std::string& path) {
  ImportedClip clip;
  clip.name = anim->mName.C_Str();
  if (clip.name.empty()) clip.name = "clip" + std::to_string(index);
  const std::string where = path + ": clip '" + clip.name + "'";
  const double tps = anim->mTicksPerSecond > 0.0 ? anim->mTicksPerSecond : 25.0;
  std::vector<double> times;
  const std::vector<const aiNodeAnim*> channel =
      joint_channels(anim, s, where, &times, &clip.ignored_channels);
  double last = anim->mDuration > 0.0 ? anim->mDuration : 0.0;
  for (double t : times) last = std::max(last, t);
  const double rate = frame_rate > 0.0 ? frame_rate : key_rate(times, tps);
  clip.duration_seconds = last / tps;
  // A clip longer than a day of frames is a corrupt duration or key time (a
  // fuzzer found 1.9e34 ticks), not a recording: refuse it before sizing.
  constexpr double kMaxFrames = 30.0 * 60 * 60 * 24;
  const double span = clip.duration_seconds * rate;
  if (!(span >= 0.0 && span <= kMaxFrames))
    fail(PLEAT_ERROR_FORMAT, where + " lasts " + std::to_string(clip.duration_seconds) + " s, " +
                                 std::to_string(span) + " frames at " + std::to_string(rate) +
                                 " fps; at most " + std::to_string(static_cast<int64_t>(kMaxFrames)) +
                                 " frames are read");
  const auto frames = static_cast<int64_t>(std::floor(span + 1e-6)) + 1;
  const int32_t n = s.joint_count();
  const Eigen::Quaterniond above_rotation = rigid_rotation(above);
  Motion& m = clip.motion;
  m.skeleton = s;
  m.frame_rate = rate;
  m.frame_count = frames;
  m.rotations.resize(static_cast<size_t>(frames * n));
  m.root_translation.resize(frames, 3);
  for (int64_t f = 0; f < frames; ++f) {
    const double tick = static_cast<double>(f) / rate * tps;
    Eigen::Quaterniond* out = m.rotations.data() + f * n;
    for (int32_t j = 0; j < n; ++j) {
      const aiNodeAnim* ch = channel[static_cast<size_t>(j)];
      if (!ch || ch->mNumRotationKeys == 0) {
        out[j] = Eigen::Quaterniond::Identity();
        continue;
      }
      Eigen::Quaterniond local = sample_rotation(ch, tick);
      if (j == 0) local = above_rotation * local;
      out[j] = (s.rest_rotation[static_cast<size_t>(j)].conjugate() * local).normalized();
    }
    const aiNodeAnim* rc = channel[0];
    if (rc && rc->mNumPositionKeys > 0) {
      const Eigen::Vector3d local = sample_position(rc, tick);
      m.root_translation.row(f) =
          (above * Eigen::Vector4d(local.x(), local.y(), local.z(), 1.0)).head<3>().transpose();
    } else {
      m.root_translation.row(f) = s.rest_translation.row(0);
    }
  }
  return clip;
}

}  // namespace

ImportedRig import_rig(const std::string& path, const RigImportOptions& options) {
  if (!(options.scale > 0.0) || !std::isfinite(options.scale))
    fail(PLEAT_ERROR_INVALID_ARGUMENT, path + ": scale must be positive and finite");
  if (!(options.frame_rate >= 0.0) || !std::isfinite(options.frame_rate))
    fail(PLEAT_ERROR_INVALID_ARGUMENT, path + ": frame_rate must be >= 0 (0 = the key rate)");
  const SceneFile file(path);
  const aiScene* scene = &file.scene();

  ImportedRig rig;
  rig.unit_scale = file.unit_scale() * options.scale;
  Eigen::Matrix4d unit = Eigen::Matrix4d::Identity();
  unit.topLeftCorner<3, 3>() *= rig.unit_scale;

  std::vector<Instance> instances;
  collect_instances(scene, scene->mRootNode, &instances);
  if (instances.empty()) fail(PLEAT_ERROR_FORMAT, path + ": the file holds no triangle mesh");
  const Joints joints = find_joints(scene, instances, path);
  Matrices world;
  rig.body.skeleton = rest_skeleton(joints, unit, path, &world);

  std::vector<double> xyz;
  std::vector<int32_t> tri;
  SkinWeights& w = rig.body.weights;
  w.joint_count = rig.body.skeleton.joint_count();
  w.offsets.assign(1, 0);
  for (const Instance& in : instances)
    add_rest_mesh(in, joints, world, unit, path, &xyz, &tri, &w, &rig.unweighted_vertices);
  if (tri.empty()) fail(PLEAT_ERROR_FORMAT, path + ": the file holds no triangles");
  normalize_skin_weights(&w, path);
  rig.body.source = path;
  rig.body.rest.vertices = Eigen::Map<Points3d>(xyz.data(), static_cast<Eigen::Index>(xyz.size() / 3), 3);
  rig.body.rest.triangles = Eigen::Map<Triangles>(tri.data(), static_cast<Eigen::Index>(tri.size() / 3), 3);
  validate_body(rig.body, path);

  const aiNode* above_root = joints.nodes[0]->mParent;
  const Eigen::Matrix4d above = above_root ? Eigen::Matrix4d(unit * global_of(above_root)) : unit;
  for (unsigned a = 0; a < scene->mNumAnimations; ++a)
    rig.clips.push_back(
        import_clip(scene->mAnimations[a], a, rig.body.skeleton, above, options.frame_rate, path));
  return rig;
}

}  // namespace pleat
