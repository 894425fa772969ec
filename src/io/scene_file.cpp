#include "io/scene_file.h"

#include <assimp/BaseImporter.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "core/error.h"
#include "io/fbx_precheck.h"
#include "io/gltf_scene.h"

namespace pleat {
namespace {

// True when the file starts with the binary glTF magic. Binary glTF declares
// the file's length and its first chunk's length in the 16-byte header;
// assimp 5.2 allocated the chunk before comparing it with the file (a 1 kB
// file asked for 4 GB; found by fuzz_glb). A header that declares more than
// the file holds is refused here with the numbers, before any reader runs.
bool check_binary_gltf_header(const std::string& path, std::ifstream& in) {
  unsigned char h[16] = {};
  in.read(reinterpret_cast<char*>(h), sizeof(h));
  if (in.gcount() < 4 || std::memcmp(h, "glTF", 4) != 0) return false;
  if (in.gcount() < static_cast<std::streamsize>(sizeof(h)))
    return true;  // the glTF reader names what is missing
  const auto u32 = [&](int at) {
    return uint64_t(h[at]) | uint64_t(h[at + 1]) << 8 | uint64_t(h[at + 2]) << 16 | uint64_t(h[at + 3]) << 24;
  };
  const uint64_t size = std::filesystem::file_size(path);
  if (u32(8) > size || u32(12) > size)
    fail(PLEAT_ERROR_FORMAT, path + ": binary glTF header declares " + std::to_string(u32(8)) +
                                 " bytes and a first chunk of " + std::to_string(u32(12)) +
                                 " bytes; the file has " + std::to_string(size));
  return true;
}

void check_fbx(const std::string& path, std::ifstream& in) {
  in.clear();
  in.seekg(0);
  check_fbx_before_assimp(path,
                          std::string{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()});
}

// glTF is io/gltf_scene's alone: assimp's own glTF importers are removed, so
// that a glTF file under another extension does not reach them by assimp's
// guess of the format.
void remove_gltf_importers(Assimp::Importer* importer) {
  for (const char* extension : {"gltf", "glb"})
    while (Assimp::BaseImporter* gltf = importer->GetImporter(extension)) {
      importer->UnregisterLoader(gltf);
      delete gltf;  // the importer deletes only the loaders it still holds
    }
}

}  // namespace

SceneFile::SceneFile(const std::string& path) {
  std::ifstream probe(path, std::ios::binary);
  if (!probe) fail(PLEAT_ERROR_IO, path + ": cannot open the file");
  if (std::filesystem::is_directory(path)) fail(PLEAT_ERROR_IO, path + ": is a directory");
  const bool binary_gltf = check_binary_gltf_header(path, probe);
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (binary_gltf || extension == ".gltf" || extension == ".glb") {
    gltf_ = read_gltf_scene(path);
    scene_ = gltf_.get();
    return;
  }
  if (extension == ".fbx") check_fbx(path, probe);
  importer_ = std::make_unique<Assimp::Importer>();
  remove_gltf_importers(importer_.get());
  importer_->SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  importer_->SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
  // ValidateDataStructure: assimp checks every mesh, face and node index of
  // the scene it built from a damaged file before we walk it.
  scene_ = importer_->ReadFile(path, aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                                         aiProcess_SortByPType | aiProcess_JoinIdenticalVertices);
  if (!scene_ || !scene_->mRootNode)
    fail(PLEAT_ERROR_FORMAT, path + ": cannot read the file: " + importer_->GetErrorString());
}

SceneFile::~SceneFile() = default;

double SceneFile::unit_scale() const {
  const aiMetadata* meta = scene_->mMetaData;
  if (!meta) return 1.0;
  double factor = 0.0;
  float factor_f = 0.0f;
  if (meta->Get("UnitScaleFactor", factor) && factor > 0.0) return factor / 100.0;
  if (meta->Get("UnitScaleFactor", factor_f) && factor_f > 0.0f) return factor_f / 100.0;
  return 1.0;
}

}  // namespace pleat
