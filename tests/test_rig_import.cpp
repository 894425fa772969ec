// Skinned characters through assimp (src/body/rig_import.*): a two-bone chain
// with weights and a two-key clip, written by assimp's own glTF 2 exporter,
// read back and posed; expected positions are worked out by hand.
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <assimp/Exporter.hpp>
#include <cmath>
#include <fstream>

#include "body/body.h"
#include "body/body_source.h"
#include "body/rig_import.h"
#include "support/expect_error.h"
#include "support/rigged_export.h"
#include "support/test_support.h"

using namespace pleat;

namespace {

const double kPi = 3.14159265358979323846;

aiQuaternion ai_quat(const Eigen::Quaterniond& q) {
  return aiQuaternion(static_cast<float>(q.w()), static_cast<float>(q.x()), static_cast<float>(q.y()),
                      static_cast<float>(q.z()));
}

aiMatrix4x4 ai_matrix(const Eigen::Affine3d& a) {
  const Eigen::Matrix4d m = a.matrix();
  aiMatrix4x4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r[i][j] = static_cast<float>(m(i, j));
  return r;
}

Eigen::Quaterniond ry90() {
  return Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()));
}
Eigen::Quaterniond rz90() {
  return Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()));
}

// Rest vertices, their (bone0, bone1) weights.
const double kVertices[6][3] = {{0.2, 0, 0}, {0.2, 1, 0},  {0.2, 1.5, 0},
                                {0.2, 2, 0}, {-0.2, 0, 0}, {-0.2, 2, 0}};
const double kWeight1[6] = {0.0, 0.5, 0.75, 1.0, 0.0, 1.0};  // bone0 gets 1 - this

// Scene: root -> {mesh node, bone0 -> bone1}. bone0 at the origin, bone1 one
// unit up with a 90 degree rest rotation about Y. Clip "wave" (1 tick per
// second, keys at 0 and 1 s): bone0 slides to x = 1, bone1 turns 90 degrees
// about its local Z. `last_key` and `bone0_rotation` make broken clips: a
// second key far in the future, a key that is no rotation.
void export_rig(const std::string& path, const char* format, double last_key = 1.0,
                aiQuaternion bone0_rotation = aiQuaternion()) {
  aiScene scene;
  scene.mRootNode = new aiNode("root");
  scene.mMaterials = new aiMaterial* [1] { new aiMaterial() };
  scene.mNumMaterials = 1;
  auto* mesh_node = new aiNode("body_mesh");
  auto* bone0 = new aiNode("bone0");
  auto* bone1 = new aiNode("bone1");
  scene.mRootNode->addChildren(2, std::array<aiNode*, 2>{mesh_node, bone0}.data());
  bone0->addChildren(1, &bone1);
  const Eigen::Affine3d bind1 = Eigen::Translation3d(0, 1, 0) * ry90();
  bone1->mTransformation = ai_matrix(bind1);
  mesh_node->mMeshes = new unsigned[1]{0};
  mesh_node->mNumMeshes = 1;

  scene.mMeshes = new aiMesh* [1] { new aiMesh() };
  scene.mNumMeshes = 1;
  aiMesh* mesh = scene.mMeshes[0];
  mesh->mName = "body";
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  mesh->mNumVertices = 6;
  mesh->mVertices = new aiVector3D[6];
  for (int i = 0; i < 6; ++i)
    mesh->mVertices[i] = aiVector3D(static_cast<float>(kVertices[i][0]), static_cast<float>(kVertices[i][1]),
                                    static_cast<float>(kVertices[i][2]));
  const unsigned tri[4][3] = {{0, 1, 4}, {4, 1, 5}, {1, 2, 5}, {2, 3, 5}};
  mesh->mNumFaces = 4;
  mesh->mFaces = new aiFace[4];
  for (int f = 0; f < 4; ++f) {
    mesh->mFaces[f].mNumIndices = 3;
    mesh->mFaces[f].mIndices = new unsigned[3]{tri[f][0], tri[f][1], tri[f][2]};
  }
  mesh->mNumBones = 2;
  mesh->mBones = new aiBone* [2] { new aiBone(), new aiBone() };
  for (int b = 0; b < 2; ++b) {
    aiBone* bone = mesh->mBones[b];
    bone->mName = b == 0 ? "bone0" : "bone1";
    bone->mOffsetMatrix = b == 0 ? aiMatrix4x4() : ai_matrix(bind1.inverse());
    std::vector<aiVertexWeight> ws;
    for (unsigned v = 0; v < 6; ++v) {
      const double x = b == 0 ? 1.0 - kWeight1[v] : kWeight1[v];
      if (x > 0) ws.emplace_back(v, static_cast<float>(x));
    }
    bone->mNumWeights = static_cast<unsigned>(ws.size());
    bone->mWeights = new aiVertexWeight[ws.size()];
    std::copy(ws.begin(), ws.end(), bone->mWeights);
  }

  scene.mNumAnimations = 1;
  scene.mAnimations = new aiAnimation* [1] { new aiAnimation() };
  aiAnimation* anim = scene.mAnimations[0];
  anim->mName = "wave";
  anim->mTicksPerSecond = 1.0;
  anim->mDuration = 1.0;
  anim->mNumChannels = 2;
  anim->mChannels = new aiNodeAnim* [2] { new aiNodeAnim(), new aiNodeAnim() };
  for (int c = 0; c < 2; ++c) {
    aiNodeAnim* ch = anim->mChannels[c];
    ch->mNodeName = c == 0 ? "bone0" : "bone1";
    ch->mNumPositionKeys = ch->mNumRotationKeys = ch->mNumScalingKeys = 2;
    ch->mPositionKeys = new aiVectorKey[2];
    ch->mRotationKeys = new aiQuatKey[2];
    ch->mScalingKeys = new aiVectorKey[2];
    for (int k = 0; k < 2; ++k) {
      const double t = k == 0 ? 0.0 : last_key;
      ch->mScalingKeys[k] = aiVectorKey(t, aiVector3D(1, 1, 1));
      if (c == 0) {
        ch->mPositionKeys[k] = aiVectorKey(t, aiVector3D(static_cast<float>(k), 0, 0));
        ch->mRotationKeys[k] = aiQuatKey(t, k == 0 ? bone0_rotation : aiQuaternion());
      } else {
        ch->mPositionKeys[k] = aiVectorKey(t, aiVector3D(0, 1, 0));
        ch->mRotationKeys[k] = aiQuatKey(t, ai_quat(k == 0 ? ry90() : ry90() * rz90()));
      }
    }
  }
  Assimp::Exporter exporter;
  ASSERT_EQ(exporter.Export(&scene, format, path), aiReturn_SUCCESS) << exporter.GetErrorString();
}

int32_t find_vertex(const Points3d& x, double px, double py, double pz) {
  for (int32_t v = 0; v < x.rows(); ++v)
    if ((x.row(v) - Eigen::RowVector3d(px, py, pz)).norm() < 1e-5) return v;
  return -1;
}

}  // namespace

TEST(RigImport, GltfChainSkeletonWeightsAndClip) {
  const std::string path = pleat_test::temp_dir("rig_gltf") + "/chain.gltf";
  export_rig(path, "gltf2");
  const ImportedRig rig = import_rig(path);
  const Body& body = rig.body;

  // Skeleton: bone0 (root, at the origin) -> bone1 (one up, rest rotation Ry 90).
  ASSERT_EQ(body.skeleton.joint_count(), 2);
  EXPECT_EQ(body.skeleton.names, (std::vector<std::string>{"bone0", "bone1"}));
  EXPECT_EQ(body.skeleton.parents, (std::vector<int32_t>{-1, 0}));
  EXPECT_LT(body.skeleton.rest_translation.row(0).norm(), 1e-6);
  EXPECT_LT((body.skeleton.rest_translation.row(1) - Eigen::RowVector3d(0, 1, 0)).norm(), 1e-6);
  EXPECT_LT(body.skeleton.rest_rotation[1].angularDistance(ry90()), 1e-6);
  EXPECT_DOUBLE_EQ(rig.unit_scale, 1.0);
  EXPECT_TRUE(rig.unweighted_vertices.empty());

  // Rest mesh and weights, found by position (the importer may reorder).
  ASSERT_EQ(body.vertex_count(), 6);
  EXPECT_EQ(body.rest.triangle_count(), 4);
  std::vector<int32_t> ids;
  for (int i = 0; i < 6; ++i) {
    ids.push_back(find_vertex(body.rest.vertices, kVertices[i][0], kVertices[i][1], kVertices[i][2]));
    ASSERT_GE(ids.back(), 0) << "rest vertex " << i;
    const Eigen::MatrixXd dense = dense_skin_weights(body.weights);
    EXPECT_NEAR(dense(ids.back(), 1), kWeight1[i], 1e-6) << "vertex " << i;
    EXPECT_NEAR(dense(ids.back(), 0), 1.0 - kWeight1[i], 1e-6) << "vertex " << i;
  }

  // The clip: key rate 1 fps, two frames.
  ASSERT_EQ(rig.clips.size(), 1u);
  const ImportedClip& clip = rig.clips[0];
  EXPECT_EQ(clip.name, "wave");
  EXPECT_NEAR(clip.duration_seconds, 1.0, 1e-9);
  EXPECT_DOUBLE_EQ(clip.motion.frame_rate, 1.0);
  ASSERT_EQ(clip.motion.frame_count, 2);
  EXPECT_LT(clip.motion.frame(1)[1].angularDistance(rz90()), 1e-6);  // relative to the rest Ry 90

  // Frame 0 is the rest pose; at frame 1, S0 = translate(1,0,0) and
  // S1 = translate(1,1,0) Rx(90) translate(0,-1,0), since
  // Ry90 Rz90 Ry90^-1 = Rx90 (Ry90 takes z to x).
  const Points3d posed = pose_body_frames(body, clip.motion, 0, 2);
  const Eigen::Index v = body.vertex_count();
  EXPECT_LT((posed.topRows(v) - body.rest.vertices).cwiseAbs().maxCoeff(), 1e-6);
  const double expected[6][3] = {{1.2, 0, 0}, {1.2, 1, 0}, {1.2, 1.125, 0.375},
                                 {1.2, 1, 1}, {0.8, 0, 0}, {0.8, 1, 1}};
  for (int i = 0; i < 6; ++i)
    EXPECT_LT((posed.row(v + ids[static_cast<size_t>(i)]) -
               Eigen::RowVector3d(expected[i][0], expected[i][1], expected[i][2]))
                  .norm(),
              1e-5)
        << "vertex " << i << " at " << posed.row(v + ids[static_cast<size_t>(i)]);

  // Resampled at 4 fps: 5 frames, the half-way frame slerps/lerps.
  RigImportOptions options;
  options.frame_rate = 4.0;
  const ImportedRig fine = import_rig(path, options);
  const Motion& m = fine.clips[0].motion;
  ASSERT_EQ(m.frame_count, 5);
  EXPECT_LT((m.root_translation.row(2) - Eigen::RowVector3d(0.5, 0, 0)).norm(), 1e-6);
  const Eigen::Quaterniond half(Eigen::AngleAxisd(kPi / 4, Eigen::Vector3d::UnitZ()));
  EXPECT_LT(m.frame(2)[1].angularDistance(half), 1e-6);
  const Points3d last = pose_body_frames(fine.body, m, 4, 1);
  EXPECT_LT((last.row(ids[3]) - Eigen::RowVector3d(1.2, 1, 1)).norm(), 1e-5);
}

// assimp 5.2's binary FBX writer emits files its own reader rejects once
// bones are present ("block offset is out of range"), so the fixture is ASCII FBX.
TEST(RigImport, FbxUnitsRestAndClip) {
  const std::string path = pleat_test::temp_dir("rig_fbx") + "/chain.fbx";
  export_rig(path, "fbxa");
  const ImportedRig rig = import_rig(path);
  // assimp writes FBX in centimetres (UnitScaleFactor 1): 1 unit = 1 cm.
  const double s = rig.unit_scale;
  EXPECT_NEAR(s, 0.01, 1e-12);
  ASSERT_EQ(rig.body.vertex_count(), 6);
  const int32_t top = find_vertex(rig.body.rest.vertices, 0.2 * s, 2 * s, 0);
  EXPECT_GE(top, 0);
  const int32_t b1 = rig.body.skeleton.find("bone1");
  ASSERT_GE(b1, 1);
  const Points3d joints = rest_joint_positions(rig.body.skeleton);
  EXPECT_LT((joints.row(b1) - Eigen::RowVector3d(0, s, 0)).norm(), 1e-6);
  EXPECT_NEAR(dense_skin_weights(rig.body.weights)(top, b1), 1.0, 1e-6);
  ASSERT_EQ(rig.clips.size(), 1u);
  const Motion& m = rig.clips[0].motion;
  ASSERT_EQ(m.frame_count, 2);
  EXPECT_LT((m.root_translation.row(1) - Eigen::RowVector3d(s, 0, 0)).norm(), 1e-9);
  const Points3d posed = pose_body_frames(rig.body, m, 1, 1);
  EXPECT_LT((posed.row(top) - s * Eigen::RowVector3d(1.2, 1, 1)).norm(), 1e-7);
}

// Keys far apart (found by fuzz_rig: 1e38 ticks apart, the key rate snapped
// to 0 fps and every sample was NaN): the clip is sampled at 1 fps, no slower.
TEST(RigImport, SparseKeysSampleAtOneFramePerSecond) {
  const std::string path = pleat_test::temp_dir("rig_sparse") + "/sparse.gltf";
  export_rig(path, "gltf2", 1e4);
  const ImportedRig rig = import_rig(path);
  ASSERT_EQ(rig.clips.size(), 1u);
  const Motion& m = rig.clips[0].motion;
  EXPECT_EQ(m.frame_rate, 1.0);
  EXPECT_EQ(m.frame_count, 10001);
  for (const Eigen::Quaterniond& q : m.rotations) ASSERT_NEAR(q.norm(), 1.0, 1e-9);
  EXPECT_TRUE(m.root_translation.allFinite());
}

TEST(RigImport, BadFiles) {
  using pleat_test::expect_error;
  const std::string dir = pleat_test::temp_dir("rig_bad");
  expect_error([&] { import_rig(dir + "/absent.gltf"); }, PLEAT_ERROR_IO, "absent.gltf");
  std::ofstream(dir + "/junk.gltf") << "{ not json";
  expect_error([&] { import_rig(dir + "/junk.gltf"); }, PLEAT_ERROR_FORMAT, "junk.gltf");
  std::ofstream(dir + "/plain.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  expect_error([&] { import_rig(dir + "/plain.obj"); }, PLEAT_ERROR_FORMAT, "no bones");
  // Found by fuzz_rig: a clip whose last key lies 1e30 s ahead (its frame
  // count overflowed), and a zero rotation key.
  export_rig(dir + "/forever.gltf", "gltf2", 1e30);
  expect_error([&] { import_rig(dir + "/forever.gltf"); }, PLEAT_ERROR_FORMAT, "clip 'wave' lasts");
  export_rig(dir + "/zero.gltf", "gltf2", 1.0, aiQuaternion(0, 0, 0, 0));
  expect_error([&] { import_rig(dir + "/zero.gltf"); }, PLEAT_ERROR_INVALID_ARGUMENT,
               "joint 'bone0' rotation key 0 is not a finite rotation");
  RigImportOptions bad;
  bad.frame_rate = -1;
  expect_error([&] { import_rig(dir + "/plain.obj", bad); }, PLEAT_ERROR_INVALID_ARGUMENT, "frame_rate");
}

// A real character read by both readers: the MakeHuman body on its CMU
// skeleton, written by assimp's exporters as GLB (read by pleat's glTF scene
// walk) and as ASCII FBX (read by assimp; centimetres, vertices reordered).
// Both give back the body as written: every vertex, its weights, the joints
// and their rest offsets. assimp's glTF writer keeps four influences per
// vertex, so the 883 of 13,380 vertices with five to seven are left out of
// the weight comparison.
TEST(RigImport, MakeHumanBodyReadsTheSameFromGlbAndFbx) {
  const std::string dir = pleat_test::temp_dir("rig_makehuman");
  const BodySource source =
      load_body_source(pleat_test::asset_dir() + "/body", PLEAT_BODY_MAKEHUMAN, PLEAT_RIG_CMU_MB);
  const Body& body = source.body;
  const Eigen::MatrixXd weights = dense_skin_weights(body.weights);
  // The original vertex within 10 um of p (float files), or -1: a search of
  // the vertices sorted by x.
  std::vector<int32_t> by_x(static_cast<size_t>(body.vertex_count()));
  for (int32_t v = 0; v < body.vertex_count(); ++v) by_x[static_cast<size_t>(v)] = v;
  std::sort(by_x.begin(), by_x.end(),
            [&](int32_t a, int32_t b) { return body.rest.vertices(a, 0) < body.rest.vertices(b, 0); });
  const auto original = [&](const Eigen::RowVector3d& p) {
    auto it = std::lower_bound(by_x.begin(), by_x.end(), p.x() - 1e-5,
                               [&](int32_t v, double x) { return body.rest.vertices(v, 0) < x; });
    for (; it != by_x.end() && body.rest.vertices(*it, 0) <= p.x() + 1e-5; ++it)
      if ((body.rest.vertices.row(*it) - p).norm() < 1e-5) return *it;
    return -1;
  };
  for (const char* format : {"glb2", "fbxa"}) {
    SCOPED_TRACE(format);
    const std::string path = dir + "/body." + (std::string(format) == "glb2" ? "glb" : "fbx");
    ASSERT_EQ(pleat_test::export_rigged_body(body, path, format), "");
    const ImportedRig rig = import_rig(path);
    const double to_metres = 1.0 / rig.unit_scale;  // the file's unit is the body's metre
    ASSERT_EQ(rig.body.vertex_count(), body.vertex_count());
    EXPECT_EQ(rig.body.rest.triangle_count(), body.rest.triangle_count());
    const Skeleton& s = rig.body.skeleton;
    ASSERT_EQ(s.joint_count(), body.skeleton.joint_count());
    std::vector<int32_t> joint(static_cast<size_t>(s.joint_count()));  // original -> read
    for (int32_t j = 0; j < s.joint_count(); ++j) {
      joint[static_cast<size_t>(j)] = s.find(body.skeleton.names[static_cast<size_t>(j)]);
      ASSERT_GE(joint[static_cast<size_t>(j)], 0) << body.skeleton.names[static_cast<size_t>(j)];
    }
    for (int32_t j = 0; j < s.joint_count(); ++j) {
      const int32_t k = joint[static_cast<size_t>(j)], parent = body.skeleton.parents[static_cast<size_t>(j)];
      EXPECT_EQ(s.parents[static_cast<size_t>(k)], parent < 0 ? -1 : joint[static_cast<size_t>(parent)]);
      EXPECT_LT((to_metres * s.rest_translation.row(k) - body.skeleton.rest_translation.row(j)).norm(), 1e-5)
          << body.skeleton.names[static_cast<size_t>(j)];
    }
    const Eigen::MatrixXd read = dense_skin_weights(rig.body.weights);
    int32_t matched = 0, compared = 0;
    double worst = 0.0;
    for (int32_t v = 0; v < rig.body.vertex_count(); ++v) {
      const int32_t o = original(to_metres * rig.body.rest.vertices.row(v));
      if (o < 0) continue;
      ++matched;
      if (body.weights.offsets[o + 1] - body.weights.offsets[o] > 4) continue;
      ++compared;
      for (int32_t j = 0; j < s.joint_count(); ++j)
        worst = std::max(worst, std::abs(read(v, joint[static_cast<size_t>(j)]) - weights(o, j)));
    }
    EXPECT_EQ(matched, body.vertex_count());
    EXPECT_GE(compared, 12000);
    EXPECT_LT(worst, 1e-5);
  }
}
