#include "io/assimp_units.h"

#include <assimp/scene.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace pleat {
namespace {

// Binary glTF (v1 and v2) declares the file's length and its first chunk's
// length in the 16-byte header; assimp 5.2 allocates the chunk before it
// compares it with the file, so a 1 kB file can ask for 4 GB. Refused here.
void check_binary_gltf_header(const std::string& path, std::ifstream& in) {
  unsigned char h[16] = {};
  in.read(reinterpret_cast<char*>(h), sizeof(h));
  if (in.gcount() < static_cast<std::streamsize>(sizeof(h)) || std::memcmp(h, "glTF", 4) != 0) return;
  const auto u32 = [&](int at) {
    return uint64_t(h[at]) | uint64_t(h[at + 1]) << 8 | uint64_t(h[at + 2]) << 16 | uint64_t(h[at + 3]) << 24;
  };
  const uint64_t size = std::filesystem::file_size(path);
  if (u32(8) > size || u32(12) > size)
    fail(PLEAT_ERROR_FORMAT, path + ": binary glTF header declares " + std::to_string(u32(8)) +
                                 " bytes and a first chunk of " + std::to_string(u32(12)) +
                                 " bytes; the file has " + std::to_string(size));
}

}  // namespace

void check_assimp_input(const std::string& path) {
  std::ifstream probe(path, std::ios::binary);
  if (!probe) fail(PLEAT_ERROR_IO, path + ": cannot open the file");
  if (std::filesystem::is_directory(path)) fail(PLEAT_ERROR_IO, path + ": is a directory");
  check_binary_gltf_header(path, probe);
}

double scene_unit_scale(const aiScene* scene) {
  if (!scene->mMetaData) return 1.0;
  double factor = 0.0;
  float factor_f = 0.0f;
  if (scene->mMetaData->Get("UnitScaleFactor", factor) && factor > 0.0) return factor / 100.0;
  if (scene->mMetaData->Get("UnitScaleFactor", factor_f) && factor_f > 0.0f) return factor_f / 100.0;
  return 1.0;
}

}  // namespace pleat
