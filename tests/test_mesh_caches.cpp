// Point caches that carry the mesh: glTF morph-target animation (written and
// read) and USD ASCII time samples (written). The glTF reader is checked on a
// file built by hand here (external buffer, strided view, STEP and
// CUBICSPLINE keys), the writer's JSON against what glTF asks, and the USD
// text against the exact expected text.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/point_cache.h"
#include "support/expect_error.h"
#include "support/test_support.h"

namespace pleat {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using pleat_test::expect_error;

class MeshCaches : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = pleat_test::temp_dir("mesh_caches"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return dir_ + "/" + name; }
  std::string dir_;
};

Triangles two_triangles() {
  Triangles t(2, 3);
  t << 0, 1, 2, 0, 2, 3;
  return t;
}

// 4 vertices moving along a wave, frame f at f * stride.
std::vector<float> wave(size_t frames, size_t stride) {
  std::vector<float> x(frames * stride, 99.0f);
  for (size_t f = 0; f < frames; ++f)
    for (size_t i = 0; i < 12; ++i)
      x[f * stride + i] = std::sin(0.7f * static_cast<float>(f) + 1.3f * static_cast<float>(i));
  return x;
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST_F(MeshCaches, GltfRoundTripsWithinFloatRounding) {
  const size_t frames = 6, stride = 14;
  const std::vector<float> x = wave(frames, stride);
  const Triangles tri = two_triangles();
  for (const char* name : {"a.gltf", "a.glb", "A.GLB"}) {
    SCOPED_TRACE(name);
    write_cache(path(name), CacheFormat::automatic, x.data(), frames, 4, stride, 24.0, &tri);
    const CacheHeader h = read_cache_header(path(name), CacheFormat::automatic);
    EXPECT_EQ(h.format, CacheFormat::gltf);
    EXPECT_EQ(h.frame_count, 6);
    EXPECT_EQ(h.vertex_count, 4);
    EXPECT_NEAR(h.frame_rate, 24.0, 1e-4);
    EXPECT_EQ(h.start_time, 0.0);
    std::vector<float> y(frames * 12);
    read_cache(path(name), CacheFormat::gltf, y.data(), 0, y.size());
    for (size_t f = 0; f < frames; ++f)
      for (size_t i = 0; i < 12; ++i) ASSERT_NEAR(y[f * 12 + i], x[f * stride + i], 1e-6) << f << " " << i;
  }
  EXPECT_EQ(read_all(path("a.glb")).substr(0, 4), "glTF");
}

// What Blender's importer relies on: targets = frames - 1, their names, one
// LINEAR weights channel whose key f sets target f - 1 alone, POSITION bounds.
TEST_F(MeshCaches, GltfWritesOneMorphTargetPerFrameAfterTheFirst) {
  const std::vector<float> x = wave(4, 12);
  const Triangles tri = two_triangles();
  write_cache(path("m.gltf"), CacheFormat::gltf, x.data(), 4, 4, 0, 30.0, &tri);
  const Json j = Json::parse(read_all(path("m.gltf")));
  EXPECT_EQ(j["asset"]["version"], "2.0");
  EXPECT_EQ(j["buffers"].size(), 1u);
  EXPECT_EQ(j["buffers"][0]["uri"].get<std::string>().rfind("data:application/octet-stream;base64,", 0), 0u);
  const Json& primitive = j["meshes"][0]["primitives"][0];
  EXPECT_EQ(primitive["targets"].size(), 3u);
  EXPECT_EQ(j["meshes"][0]["extras"]["targetNames"], Json({"frame_0001", "frame_0002", "frame_0003"}));
  EXPECT_EQ(j["meshes"][0]["weights"], Json({0.0, 0.0, 0.0}));
  const Json& indices = j["accessors"][primitive["indices"].get<int>()];
  EXPECT_EQ(indices["count"], 6);
  EXPECT_EQ(indices["componentType"], 5125);
  const Json& position = j["accessors"][primitive["attributes"]["POSITION"].get<int>()];
  EXPECT_EQ(position["count"], 4);
  for (int k = 0; k < 3; ++k) {
    float lo = 1e9f, hi = -1e9f;
    for (int v = 0; v < 4; ++v) lo = std::min(lo, x[3 * v + k]), hi = std::max(hi, x[3 * v + k]);
    EXPECT_FLOAT_EQ(position["min"][k].get<float>(), lo);
    EXPECT_FLOAT_EQ(position["max"][k].get<float>(), hi);
  }
  const Json& animation = j["animations"][0];
  EXPECT_EQ(animation["channels"][0]["target"]["path"], "weights");
  EXPECT_EQ(animation["samplers"][0]["interpolation"], "LINEAR");
  const Json& times = j["accessors"][animation["samplers"][0]["input"].get<int>()];
  EXPECT_EQ(times["count"], 4);
  EXPECT_FLOAT_EQ(times["max"][0].get<float>(), 0.1f);
  EXPECT_EQ(j["accessors"][animation["samplers"][0]["output"].get<int>()]["count"], 12);
}

TEST_F(MeshCaches, GltfOfOneFrameHasNoAnimation) {
  const std::vector<float> x = wave(1, 12);
  const Triangles tri = two_triangles();
  write_cache(path("one.gltf"), CacheFormat::gltf, x.data(), 1, 4, 0, 30.0, &tri);
  const Json j = Json::parse(read_all(path("one.gltf")));
  EXPECT_FALSE(j.contains("animations"));
  EXPECT_EQ(read_cache_header(path("one.gltf"), CacheFormat::automatic).frame_count, 1);
}

// A triangle with two targets; keys at 0.5, 1.0, 1.5 s. The base positions
// sit in a view with a 16-byte stride; everything is in an external .bin.
struct HandBuiltGltf {
  Json json;
  std::vector<float> bin;
};

HandBuiltGltf hand_built(bool cubic) {
  HandBuiltGltf g;
  g.bin = {0,    0,    0,   -7, 1, 0, 0, -7, 0, 1, 0, -7,  // base, stride 16
           0,    0,    1,   0,  0, 1, 0, 0,  1,            // target 0: lift all by 1
           0,    0,    0,   0,  0, 0, 1, 0,  0,            // target 1: vertex 2 along x
           0.5f, 1.0f, 1.5f};
  const std::vector<float> weights = {0, 0, 0.5f, 0, 0.25f, 2};
  for (size_t k = 0; k < 3; ++k)
    for (int part = 0; part < (cubic ? 3 : 1); ++part) {
      const bool value = !cubic || part == 1;  // tangents are never the value
      g.bin.push_back(value ? weights[2 * k] : -100.0f);
      g.bin.push_back(value ? weights[2 * k + 1] : -100.0f);
    }
  const size_t weight_bytes = (cubic ? 18 : 6) * 4;
  g.json = Json::parse(R"({
    "asset": {"version": "2.0"},
    "bufferViews": [
      {"buffer": 0, "byteOffset": 0, "byteLength": 48, "byteStride": 16},
      {"buffer": 0, "byteOffset": 48, "byteLength": 36},
      {"buffer": 0, "byteOffset": 84, "byteLength": 36},
      {"buffer": 0, "byteOffset": 120, "byteLength": 12}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 1], "max": [0, 0, 1]},
      {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 0, 0]},
      {"bufferView": 3, "componentType": 5126, "count": 3, "type": "SCALAR", "min": [0.5], "max": [1.5]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "targets": [{"POSITION": 1}, {"POSITION": 2}]}]}],
    "nodes": [{"name": "empty"}, {"mesh": 0}],
    "scenes": [{"nodes": [0, 1]}],
    "animations": [{"samplers": [{"input": 3, "output": 4}],
                    "channels": [{"sampler": 0, "target": {"node": 1, "path": "weights"}}]}]
  })");
  g.json["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 132}, {"byteLength", weight_bytes}});
  g.json["accessors"].push_back(
      {{"bufferView", 4}, {"componentType", 5126}, {"count", cubic ? 18 : 6}, {"type", "SCALAR"}});
  g.json["animations"][0]["samplers"][0]["interpolation"] = cubic ? "CUBICSPLINE" : "STEP";
  g.json["buffers"] = Json::array({{{"uri", "hand.bin"}, {"byteLength", g.bin.size() * 4}}});
  return g;
}

void save(const HandBuiltGltf& g, const std::string& dir) {
  std::ofstream(dir + "/hand.gltf") << g.json.dump();
  std::ofstream(dir + "/hand.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(g.bin.data()), static_cast<std::streamsize>(g.bin.size() * 4));
}

TEST_F(MeshCaches, ReadsAHandBuiltGltfAtItsKeys) {
  for (bool cubic : {false, true}) {
    SCOPED_TRACE(cubic ? "CUBICSPLINE" : "STEP");
    save(hand_built(cubic), dir_);
    const CacheHeader h = read_cache_header(path("hand.gltf"), CacheFormat::automatic);
    EXPECT_EQ(h.frame_count, 3);
    EXPECT_EQ(h.vertex_count, 3);
    EXPECT_DOUBLE_EQ(h.frame_rate, 2.0);
    EXPECT_DOUBLE_EQ(h.start_time, 0.5);
    std::vector<float> y(27);
    read_cache(path("hand.gltf"), CacheFormat::gltf, y.data(), 0, y.size());
    const std::vector<float> expected = {0, 0, 0,     1, 0, 0,     0, 1, 0,     // key 0: the base
                                         0, 0, 0.5f,  1, 0, 0.5f,  0, 1, 0.5f,  // key 1: half of target 0
                                         0, 0, 0.25f, 1, 0, 0.25f, 2, 1, 0.25f};
    for (size_t i = 0; i < 27; ++i) EXPECT_FLOAT_EQ(y[i], expected[i]) << i;
  }
}

TEST_F(MeshCaches, RejectsBrokenGltfNamingTheField) {
  float y[64];
  const auto broken = [&](const std::function<void(HandBuiltGltf*)>& damage, pleat_status status,
                          const char* part) {
    HandBuiltGltf g = hand_built(false);
    damage(&g);
    save(g, dir_);
    expect_error([&] { read_cache(path("hand.gltf"), CacheFormat::automatic, y, 0, 64); }, status, part);
  };
  broken([](HandBuiltGltf* g) { g->json["accessors"][4]["count"] = 5; }, PLEAT_ERROR_FORMAT,
         "output holds 5 weights, 3 keys of 2 targets need 6");
  broken([](HandBuiltGltf* g) { g->bin[31] = 0.5f; }, PLEAT_ERROR_FORMAT, "key 1 is not later");
  broken([](HandBuiltGltf* g) { g->json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9; },
         PLEAT_ERROR_FORMAT, "accessor 9");
  broken([](HandBuiltGltf* g) { g->json["bufferViews"][0]["byteLength"] = 40; }, PLEAT_ERROR_FORMAT,
         "POSITION (accessor 0) reaches past the end");
  broken([](HandBuiltGltf* g) { g->json["accessors"][1]["type"] = "VEC2"; }, PLEAT_ERROR_FORMAT,
         "target 0 POSITION (accessor 1) has 2 components");
  broken([](HandBuiltGltf* g) { g->bin[13] = std::nanf(""); }, PLEAT_ERROR_FORMAT, "not finite");
  broken([](HandBuiltGltf* g) { g->json["nodes"][1].erase("mesh"); }, PLEAT_ERROR_FORMAT,
         "no node has a mesh");
  std::ofstream(path("text.gltf")) << "{ not json";
  expect_error([&] { read_cache_header(path("text.gltf"), CacheFormat::automatic); }, PLEAT_ERROR_FORMAT,
               "text.gltf");
  expect_error([&] { read_cache_header(path("missing.glb"), CacheFormat::automatic); }, PLEAT_ERROR_IO,
               "missing.glb");
}

TEST_F(MeshCaches, UsdaHoldsEveryFrameAsATimeSample) {
  const std::vector<float> x = {0, 0.5f, 1.25f, -2, 0, 0, 0, 1, 0,  // frame 0
                                0, 0.5f, 1.5f,  -2, 0, 0, 0, 1, 1e-3f};
  Triangles tri(1, 3);
  tri << 0, 2, 1;
  write_cache(path("a.usda"), CacheFormat::automatic, x.data(), 2, 3, 0, 24.0, &tri);
  EXPECT_EQ(read_all(path("a.usda")), R"(#usda 1.0
(
    defaultPrim = "garment"
    startTimeCode = 0
    endTimeCode = 1
    timeCodesPerSecond = 24
    framesPerSecond = 24
    metersPerUnit = 1
    upAxis = "Y"
)

def Xform "garment"
{
    def Mesh "mesh"
    {
        uniform token subdivisionScheme = "none"
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 2, 1]
        point3f[] points = [(0, 0.5, 1.25), (-2, 0, 0), (0, 1, 0)]
        point3f[] points.timeSamples = {
            0: [(0, 0.5, 1.25), (-2, 0, 0), (0, 1, 0)],
            1: [(0, 0.5, 1.5), (-2, 0, 0), (0, 1, 0.001)],
        }
    }
}
)");
  expect_error([&] { read_cache_header(path("a.usda"), CacheFormat::automatic); },
               PLEAT_ERROR_INVALID_ARGUMENT, "does not read them");
}

TEST_F(MeshCaches, RejectedWritesLeaveNothingBehind) {
  std::vector<float> x = wave(3, 12);
  const Triangles tri = two_triangles();
  for (const char* name : {"n.gltf", "n.glb", "n.usda"}) {
    SCOPED_TRACE(name);
    expect_error([&] { write_cache(path(name), CacheFormat::automatic, x.data(), 3, 4, 0, 30, nullptr); },
                 PLEAT_ERROR_INVALID_ARGUMENT, "triangles");
    x[2 * 12 + 7] = std::nanf("");
    expect_error([&] { write_cache(path(name), CacheFormat::automatic, x.data(), 3, 4, 0, 30, &tri); },
                 PLEAT_ERROR_INVALID_ARGUMENT, "frame 2 vertex 2");
    x[2 * 12 + 7] = 0.0f;
  }
  EXPECT_TRUE(fs::is_empty(dir_));
}

}  // namespace
}  // namespace pleat
