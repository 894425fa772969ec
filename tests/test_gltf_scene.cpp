// glTF scenes read by pleat (src/io/gltf_scene.*) rather than by assimp:
// node transforms, primitive modes and indices worked out by hand, and the
// damaged files that assimp 5.2.5's own importer overran or dereferenced
// (found by the fuzz targets) refused by name. Skins and animations are
// checked through the rig importer (test_rig_import).
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "body/rig_import.h"
#include "io/gltf_scene.h"
#include "io/mesh_import.h"
#include "support/expect_error.h"
#include "support/test_support.h"

using namespace pleat;
using Json = nlohmann::json;

namespace {

// A unit quad's corners (floats) then their indices 0..3 (bytes), in quad.bin.
// Node "strip" (under "turn", a quarter turn about z) draws them as a strip,
// scaled by 2 and lifted by 2; its mesh also has a line, which is skipped.
// Node "fan" draws them as a fan, moved 10 along x by a matrix.
Json quad_scene() {
  return Json::parse(R"({
    "asset": {"version": "2.0"},
    "buffers": [{"uri": "quad.bin", "byteLength": 52}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 48, "byteLength": 4}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 1, "componentType": 5121, "count": 4, "type": "SCALAR"}],
    "meshes": [
      {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 5},
                      {"attributes": {"POSITION": 0}, "indices": 1, "mode": 1}]},
      {"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 6}]}],
    "nodes": [
      {"name": "turn", "rotation": [0, 0, 0.70710678118654752, 0.70710678118654752], "children": [1]},
      {"name": "strip", "mesh": 0, "translation": [0, 0, 2], "scale": [2, 2, 2]},
      {"name": "fan", "mesh": 1, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1]}],
    "scenes": [{"nodes": [0, 2]}]
  })");
}

class GltfScene : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = pleat_test::temp_dir("gltf_scene");
    const float corners[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    const uint8_t indices[4] = {0, 1, 2, 3};
    std::ofstream bin(dir_ + "/quad.bin", std::ios::binary);
    bin.write(reinterpret_cast<const char*>(corners), sizeof(corners));
    bin.write(reinterpret_cast<const char*>(indices), sizeof(indices));
  }

  std::string save(const Json& scene, const std::string& name = "quad.gltf") const {
    std::ofstream(dir_ + "/" + name) << scene.dump();
    return dir_ + "/" + name;
  }

  std::string dir_;
};

TEST_F(GltfScene, TransformsModesAndIndicesAsWorkedOutByHand) {
  const ImportedMesh mesh = import_mesh(save(quad_scene()));
  ASSERT_EQ(mesh.vertices.rows(), 8);
  EXPECT_EQ(mesh.unit_scale, 1.0);
  // strip: turn * (lift + 2 p), the quarter turn taking (x, y) to (-y, x).
  const double expected[8][3] = {{0, 0, 2},  {0, 2, 2},  {-2, 0, 2}, {-2, 2, 2},
                                 {10, 0, 0}, {11, 0, 0}, {10, 1, 0}, {11, 1, 0}};
  for (int v = 0; v < 8; ++v)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mesh.vertices(v, c), expected[v][c], 1e-6) << v << "," << c;
  // A strip alternates its winding; a fan turns about its first vertex.
  const int triangles[4][3] = {{0, 1, 2}, {2, 1, 3}, {4, 5, 6}, {4, 6, 7}};
  ASSERT_EQ(mesh.triangles.rows(), 4);
  for (int t = 0; t < 4; ++t)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(mesh.triangles(t, c), triangles[t][c]) << t;
}

// The importers find bones and channels by node name, so every node gets a
// name of its own: unnamed ones their index, a repeated name (or the name of
// the scene's own root) the index after it.
TEST_F(GltfScene, EveryNodeIsNamedOnce) {
  Json scene = quad_scene();
  scene["nodes"][0]["name"] = "strip";
  scene["nodes"][2].erase("name");
  scene["nodes"].push_back({{"name", "(glTF scene)"}});
  scene["scenes"][0]["nodes"].push_back(3);
  const std::unique_ptr<aiScene> read = read_gltf_scene(save(scene));
  const aiNode* root = read->mRootNode;
  EXPECT_STREQ(root->mName.C_Str(), "(glTF scene)");
  ASSERT_EQ(root->mNumChildren, 3u);
  EXPECT_STREQ(root->mChildren[0]->mName.C_Str(), "strip");
  ASSERT_EQ(root->mChildren[0]->mNumChildren, 1u);
  EXPECT_STREQ(root->mChildren[0]->mChildren[0]->mName.C_Str(), "strip#1");
  EXPECT_STREQ(root->mChildren[1]->mName.C_Str(), "node2");
  EXPECT_STREQ(root->mChildren[2]->mName.C_Str(), "(glTF scene)#3");
  EXPECT_EQ(root->mChildren[0]->mChildren[0]->mParent, root->mChildren[0]);
}

// Two nodes showing one mesh share its aiMesh (as assimp's importer builds
// them); the garment gets both instances, each under its own transform.
TEST_F(GltfScene, InstancesShareTheirMesh) {
  Json scene = quad_scene();
  scene["nodes"].push_back({{"name", "fan2"}, {"mesh", 1}, {"translation", {0, 5, 0}}});
  scene["scenes"][0]["nodes"].push_back(3);
  const std::string path = save(scene);
  const std::unique_ptr<aiScene> read = read_gltf_scene(path);
  EXPECT_EQ(read->mNumMeshes, 2u);  // the strip and the fan, once each
  const aiNode* fan = read->mRootNode->mChildren[1];
  const aiNode* fan2 = read->mRootNode->mChildren[2];
  ASSERT_EQ(fan->mNumMeshes, 1u);
  ASSERT_EQ(fan2->mNumMeshes, 1u);
  EXPECT_EQ(fan->mMeshes[0], fan2->mMeshes[0]);
  const ImportedMesh mesh = import_mesh(path);
  ASSERT_EQ(mesh.vertices.rows(), 12);
  EXPECT_NEAR(mesh.vertices(11, 0), 1.0, 1e-6);  // the second fan's last corner: (1, 1) + (0, 5)
  EXPECT_NEAR(mesh.vertices(11, 1), 6.0, 1e-6);
}

TEST_F(GltfScene, DamagedScenesAreRefusedNamingTheField) {
  const auto broken = [&](const std::function<void(Json*)>& damage, const std::string& part) {
    Json scene = quad_scene();
    damage(&scene);
    const std::string path = save(scene);
    pleat_test::expect_error([&] { import_mesh(path); }, PLEAT_ERROR_FORMAT, part);
  };
  broken([](Json* s) { (*s)["nodes"][1]["children"] = {0}; },
         "nodes[1].children[0] reaches nodes[0] a second time");
  broken([](Json* s) { (*s)["scenes"][0]["nodes"] = {0, 1}; }, "reaches nodes[1] a second time");
  broken([](Json* s) { (*s)["nodes"][2]["matrix"] = {1, 2, 3}; }, "nodes[2].matrix has 3 numbers, not 16");
  broken([](Json* s) { (*s)["nodes"][0]["children"] = {7}; }, "nodes[0].children[0] names node 7 of 3");
  broken([](Json* s) { (*s)["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9; },
         "meshes[0].primitives[0] POSITION names accessor 9 of 2");
  broken([](Json* s) { (*s)["meshes"][1]["primitives"][0]["mode"] = 9; },
         "mode 9 is not a glTF primitive mode");
  broken([](Json* s) { (*s)["accessors"][1]["count"] = 5; }, "indices (accessor 1) reaches past the end");
  broken([](Json* s) { (*s)["accessors"][0]["componentType"] = 5123; }, "has component type 5123, not float");
  broken([](Json* s) { (*s)["nodes"][2]["mesh"] = 4; }, "nodes[2].mesh names mesh 4 of 2");
  // tinygltf's own file reader took a folder for 2^63 - 1 bytes (fuzz_gltf).
  broken([](Json* s) { (*s)["buffers"][0]["uri"] = "."; }, "is not a readable file");
  // A chain of 1,001 nodes: the importers walk trees by recursion.
  broken(
      [](Json* s) {
        for (int n = 3; n < 1003; ++n) (*s)["nodes"].push_back({{"children", {n + 1}}});
        (*s)["nodes"].push_back(Json::object());
        (*s)["scenes"][0]["nodes"] = {3};
      },
      "nodes[1003] lies deeper than 1000 levels");
  std::ofstream(dir_ + "/text.gltf") << "{ not json";
  pleat_test::expect_error([&] { import_mesh(dir_ + "/text.gltf"); }, PLEAT_ERROR_FORMAT,
                           "text.gltf': not a readable glTF file");
}

// An index past the vertices: the file is read, the index refused.
TEST_F(GltfScene, IndicesPastTheVerticesAreRefused) {
  std::fstream bin(dir_ + "/quad.bin", std::ios::binary | std::ios::in | std::ios::out);
  bin.seekp(51);
  bin.put(7);
  bin.close();
  pleat_test::expect_error([&] { import_mesh(save(quad_scene())); }, PLEAT_ERROR_FORMAT,
                           "meshes[0].primitives[0] index 3 is 7, of 4 vertices");
}

// Inputs on which assimp 5.2.5's glTF importer overran a heap buffer
// (strncmp, text and binary) or dereferenced null (a damaged rig), found by
// fuzz_gltf, fuzz_glb and fuzz_rig. pleat reads glTF itself now: each is a
// clear format error (under ASan, scripts/sanitize.sh replays them as seeds).
TEST(GltfFindings, AssimpCrashersAreFormatErrors) {
  const std::string seeds = pleat_test::source_dir() + "/tests/fuzz/seeds/";
  for (const char* name : {"gltf/finding-assimp-strncmp.gltf", "glb/finding-assimp-strncmp.glb"})
    pleat_test::expect_error([&] { import_mesh(seeds + name); }, PLEAT_ERROR_FORMAT,
                             "not a readable glTF file");
  pleat_test::expect_error([&] { import_rig(seeds + "rig/finding-assimp-null-deref.glb"); },
                           PLEAT_ERROR_FORMAT, "finding-assimp-null-deref.glb");
}

// A binary glTF is recognised by its magic whatever its extension, so it
// never reaches assimp's guess of the format.
TEST_F(GltfScene, BinaryGltfUnderAnotherExtensionIsReadByPleat) {
  const std::string rig = pleat_test::source_dir() + "/tests/fuzz/seeds/rig/chain.glb";
  std::filesystem::copy_file(rig, dir_ + "/chain.mesh", std::filesystem::copy_options::overwrite_existing);
  const ImportedMesh a = import_mesh(rig), b = import_mesh(dir_ + "/chain.mesh");
  EXPECT_GT(a.vertices.rows(), 0);
  EXPECT_TRUE(a.vertices.isApprox(b.vertices));
  EXPECT_EQ(a.triangles, b.triangles);
}

// assimp's glTF loaders are removed from the importer pleat runs, so a text
// glTF under an extension no importer claims (and without a magic to
// recognise) is refused rather than read by assimp's guess of the format.
// With the loaders left in, assimp reads this file.
TEST_F(GltfScene, TextGltfUnderAnotherExtensionNeverReachesAssimp) {
  const std::string path = save(quad_scene(), "quad.garment");
  pleat_test::expect_error([&] { import_mesh(path); }, PLEAT_ERROR_FORMAT,
                           "quad.garment: cannot read the file");
}

}  // namespace
