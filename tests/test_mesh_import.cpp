// Garments from files: OBJ, FBX and glTF through assimp. The FBX and glTF
// fixtures are written by assimp's own exporters, an independent writer.
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <assimp/Exporter.hpp>
#include <cstring>
#include <fstream>
#include <functional>

#include "body/rig_import.h"
#include "core/error.h"
#include "garment/garment.h"
#include "io/mesh_import.h"
#include "support/expect_error.h"
#include "support/test_support.h"

using namespace pleat;

namespace {

// A two-quad strip with a UV seam: the middle column exists twice.
void write_seamed_obj(const std::string& path) {
  std::ofstream out(path);
  out << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"  // left quad
         "v 1 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\n"  // right quad, seam copy of x = 1
         "vt 0 0\nvt 0.4 0\nvt 0.4 1\nvt 0 1\n"  // separate UV islands, as
         "vt 0.6 0\nvt 1 0\nvt 1 1\nvt 0.6 1\n"  // a garment's panels have
         "f 1/1 2/2 3/3 4/4\nf 5/5 6/6 7/7 8/8\n";
}

// Exports the strip through assimp in the given format id ("fbx", "gltf2", ...).
void export_strip(const std::string& path, const char* format) {
  aiScene scene;
  scene.mRootNode = new aiNode();
  scene.mMaterials = new aiMaterial* [1] { new aiMaterial() };
  scene.mNumMaterials = 1;
  scene.mMeshes = new aiMesh* [1] { new aiMesh() };
  scene.mNumMeshes = 1;
  scene.mRootNode->mMeshes = new unsigned[1]{0};
  scene.mRootNode->mNumMeshes = 1;
  aiMesh* mesh = scene.mMeshes[0];
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  const float xyz[6][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
  mesh->mNumVertices = 6;
  mesh->mVertices = new aiVector3D[6];
  for (int i = 0; i < 6; ++i) mesh->mVertices[i] = aiVector3D(xyz[i][0], xyz[i][1], xyz[i][2]);
  const unsigned tri[4][3] = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
  mesh->mNumFaces = 4;
  mesh->mFaces = new aiFace[4];
  for (int f = 0; f < 4; ++f) {
    mesh->mFaces[f].mNumIndices = 3;
    mesh->mFaces[f].mIndices = new unsigned[3]{tri[f][0], tri[f][1], tri[f][2]};
  }
  Assimp::Exporter exporter;
  ASSERT_EQ(exporter.Export(&scene, format, path), aiReturn_SUCCESS) << exporter.GetErrorString();
}

}  // namespace

TEST(MeshImport, ObjQuadsAreTriangulatedAndSeamsWelded) {
  const std::string path = pleat_test::temp_dir("import_obj") + "/strip.obj";
  write_seamed_obj(path);
  ImportedMesh m = import_mesh(path);
  EXPECT_EQ(m.triangles.rows(), 4);
  EXPECT_EQ(m.unit_scale, 1.0);
  Garment g = build_garment(m.vertices, m.triangles, {}, path);
  EXPECT_EQ(g.report.vertex_count, 6u);
  EXPECT_EQ(g.report.welded_vertex_count, 2u);
  EXPECT_EQ(g.report.component_count, 1u);
  EXPECT_EQ(g.report.boundary_loop_count, 1u);
  EXPECT_NEAR(g.report.total_area, 2.0, 1e-12);

  GarmentBuildOptions no_weld;
  no_weld.weld_tolerance = -1.0;
  Garment split = build_garment(m.vertices, m.triangles, no_weld, path);
  EXPECT_EQ(split.report.component_count, 2u) << "without welding the seam cuts the strip in two";
}

TEST(MeshImport, GltfIsMetresAsWritten) {
  const std::string path = pleat_test::temp_dir("import_gltf") + "/strip.gltf";
  export_strip(path, "gltf2");
  ImportedMesh m = import_mesh(path);
  EXPECT_EQ(m.triangles.rows(), 4);
  EXPECT_DOUBLE_EQ(m.vertices.col(0).maxCoeff(), 2.0);
  EXPECT_DOUBLE_EQ(m.vertices.col(1).maxCoeff(), 1.0);
  Garment g = build_garment(m.vertices, m.triangles, {}, path);
  EXPECT_EQ(g.report.vertex_count, 6u);
  EXPECT_NEAR(g.report.total_area, 2.0, 1e-9);
}

TEST(MeshImport, FbxUnitIsConvertedToMetres) {
  // assimp writes UnitScaleFactor 1 (centimetres), as Maya does: 2 units = 2 cm.
  // (ASCII FBX: assimp 5.2 cannot read back its own binary FBX export.)
  const std::string path = pleat_test::temp_dir("import_fbx") + "/strip.fbx";
  export_strip(path, "fbxa");
  ImportedMesh m = import_mesh(path);
  EXPECT_EQ(m.triangles.rows(), 4);
  EXPECT_DOUBLE_EQ(m.unit_scale, 0.01);
  EXPECT_NEAR(m.vertices.col(0).maxCoeff() - m.vertices.col(0).minCoeff(), 0.02, 1e-9);
  Garment g = build_garment(m.vertices, m.triangles, {}, path);
  EXPECT_EQ(g.report.vertex_count, 6u);
}

TEST(MeshImport, UnreadableFilesNameThemselves) {
  const std::string dir = pleat_test::temp_dir("import_bad");
  std::ofstream(dir + "/noise.fbx") << "Kaydara FBX Binary  \x00\x1a\x00 truncated";
  std::ofstream(dir + "/lines.obj") << "v 0 0 0\nv 1 0 0\nl 1 2\n";
  for (const char* name : {"/noise.fbx", "/lines.obj", "/missing.gltf"}) {
    try {
      import_mesh(dir + name);
      ADD_FAILURE() << name << " loaded";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
      EXPECT_TRUE(e.status() == PLEAT_ERROR_FORMAT || e.status() == PLEAT_ERROR_IO ||
                  e.status() == PLEAT_ERROR_INVALID_MESH)
          << e.what();
    }
  }
}

// A binary glTF whose header claims a 4 GB JSON chunk in a 1 kB file (found by
// fuzz_glb: assimp allocates the chunk first) is refused before assimp runs.
TEST(MeshImport, BinaryGltfLengthsBeyondTheFileAreRefused) {
  const std::string path = pleat_test::source_dir() + "/tests/fuzz/seeds/glb/finding-chunk-length-4gb.glb";
  try {
    import_mesh(path);
    ADD_FAILURE() << "loaded";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), PLEAT_ERROR_FORMAT) << e.what();
    EXPECT_NE(std::string(e.what()).find("a first chunk of 4177462136 bytes; the file has 1292"),
              std::string::npos)
        << e.what();
  }
  // The same check guards rigged characters.
  EXPECT_THROW(pleat::import_rig(path), Error);
}

namespace {

// Binary FBX 7.4 (32-bit offsets): the header, then records.
std::string binary_fbx_header() {
  std::string out("Kaydara FBX Binary  \0\x1a\0", 23);
  const uint32_t version = 7400;
  out.append(reinterpret_cast<const char*>(&version), 4);
  return out;
}

std::string fbx_int64(int64_t v) {
  return "L" + std::string(reinterpret_cast<const char*>(&v), 8);
}

std::string fbx_string(const std::string& v) {
  const auto n = static_cast<uint32_t>(v.size());
  return "S" + std::string(reinterpret_cast<const char*>(&n), 4) + v;
}

// Appends one record; `children` (if any) appends the nested records, which
// a 13-byte null record closes.
void append_fbx_record(std::string* out, const std::string& name, const std::string& properties,
                       uint32_t property_count, const std::function<void()>& children = {}) {
  const size_t start = out->size();
  out->append(12, '\0');
  *out += static_cast<char>(name.size());
  *out += name + properties;
  if (children) {
    children();
    out->append(13, '\0');
  }
  const uint32_t fields[3] = {static_cast<uint32_t>(out->size()), property_count,
                              static_cast<uint32_t>(properties.size())};
  std::memcpy(&(*out)[start], fields, sizeof(fields));
}

// `depth` records named "A" nested in one another.
std::string nested_binary_fbx(int depth) {
  std::string out = binary_fbx_header();
  std::function<void(int)> record = [&](int level) {
    append_fbx_record(&out, "A", "", 0, [&] {
      if (level + 1 < depth) record(level + 1);
    });
  };
  record(0);
  out.append(13, '\0');
  return out;
}

// Two models, 1 a child of 2, and 2 a child of 1 when `cyclic` (else of the
// scene root, 0).
std::string linked_models_binary_fbx(bool cyclic) {
  std::string out = binary_fbx_header();
  append_fbx_record(&out, "Objects", "", 0, [&] {
    for (int64_t id : {1, 2}) append_fbx_record(&out, "Model", fbx_int64(id) + fbx_string("Null"), 2);
  });
  append_fbx_record(&out, "Connections", "", 0, [&] {
    append_fbx_record(&out, "C", fbx_string("OO") + fbx_int64(1) + fbx_int64(2), 3);
    append_fbx_record(&out, "C", fbx_string("OO") + fbx_int64(2) + fbx_int64(cyclic ? 1 : 0), 3);
  });
  out.append(13, '\0');
  return out;
}

}  // namespace

// assimp recurses once per FBX scope; 200,000 levels in 1 MB overflow the
// stack of any process. Such files are refused first; ordinary nesting passes
// the check (and fails later for lack of geometry).
TEST(MeshImport, FbxNestedBeyondAnyRealSceneIsRefused) {
  const std::string dir = pleat_test::temp_dir("import_deep_fbx");
  std::ofstream(dir + "/deep_ascii.fbx") << "; FBX 7.5.0 project file\n" << std::string(5000, '{');
  std::ofstream(dir + "/deep_binary.fbx", std::ios::binary) << nested_binary_fbx(200);
  std::ofstream(dir + "/shallow_binary.fbx", std::ios::binary) << nested_binary_fbx(20);
  std::ofstream(dir + "/braces_in_strings.fbx")
      << "; FBX 7.5.0 project file\nA: \"" << std::string(5000, '{') << "\" ; {{{{\n";
  for (auto [name, too_deep] : {std::pair<const char*, bool>{"/deep_ascii.fbx", true},
                                {"/deep_binary.fbx", true},
                                {"/shallow_binary.fbx", false},
                                {"/braces_in_strings.fbx", false}}) {
    try {
      import_mesh(dir + name);
      ADD_FAILURE() << name << " loaded";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).find("nested more than 64 deep") != std::string::npos, too_deep)
          << e.what();
    }
  }
}

// assimp converts FBX models by descending from the root to each model's
// children, so a model that is its own ancestor recurses until the stack
// overflows (fuzz_fbx found one connected to itself, in 8.7 kB of ASCII).
// Such files are refused first, in both encodings; a tree of models passes.
TEST(MeshImport, FbxModelCyclesAreRefused) {
  const std::string dir = pleat_test::temp_dir("import_fbx_cycles");
  std::ofstream(dir + "/cyclic.fbx", std::ios::binary) << linked_models_binary_fbx(true);
  std::ofstream(dir + "/tree.fbx", std::ios::binary) << linked_models_binary_fbx(false);
  const std::string found = pleat_test::source_dir() + "/tests/fuzz/seeds/fbx/finding-model-own-parent.fbx";
  for (auto [path, cyclic] :
       {std::pair<std::string, bool>{dir + "/cyclic.fbx", true}, {dir + "/tree.fbx", false}, {found, true}}) {
    try {
      import_mesh(path);
      ADD_FAILURE() << path << " loaded";
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), PLEAT_ERROR_FORMAT) << e.what();
      EXPECT_EQ(std::string(e.what()).find("is its own ancestor") != std::string::npos, cyclic) << e.what();
    }
  }
  EXPECT_THROW(pleat::import_rig(found), Error);
}

// assimp adds a binary record's declared lengths to pointers before comparing
// them: a property length near 2^64 wrapped, and its tokenizer aborted on an
// assertion (found by fuzz_fbx). Records must lie within their parents and
// their properties within themselves.
TEST(MeshImport, FbxRecordsReachingOutsideThemselvesAreRefused) {
  const std::string dir = pleat_test::temp_dir("import_fbx_records");
  const auto patched = [&](const std::string& name, size_t field, uint32_t value) {
    std::string bytes = linked_models_binary_fbx(false);
    std::memcpy(&bytes[27 + field * 4], &value, 4);  // of the first record, "Objects"
    std::ofstream(dir + "/" + name, std::ios::binary) << bytes;
    return dir + "/" + name;
  };
  pleat_test::expect_error([&] { import_mesh(patched("properties.fbx", 2, 0xffffffffu)); },
                           PLEAT_ERROR_FORMAT,
                           "FBX record at byte 27 declares 4294967295 bytes of properties");
  pleat_test::expect_error(
      [&] { import_mesh(patched("end.fbx", 0, 1u << 20)); }, PLEAT_ERROR_FORMAT,
      "FBX record at byte 27 ends at byte 1048576, not between its start and its parent's end");
  const std::string found =
      pleat_test::source_dir() + "/tests/fuzz/seeds/fbx/finding-property-length-wraps.fbx";
  pleat_test::expect_error([&] { import_mesh(found); }, PLEAT_ERROR_FORMAT, "FBX record at byte ");
}
