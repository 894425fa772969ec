#include "io/assimp_support.h"

#include <assimp/scene.h>

#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

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

// assimp parses FBX scopes recursively, one stack frame per level, so a
// deeply nested file overflows the stack and kills the host (`assimp info` on
// an ASCII FBX of 200,000 nested scopes, 1 MB, segfaults). Real FBX files
// nest about ten deep.
constexpr int kMaxFbxDepth = 64;

void refuse_deep_fbx(const std::string& path, int depth) {
  fail(PLEAT_ERROR_FORMAT, path + ": FBX scopes nested more than " + std::to_string(depth) +
                               " deep; no real scene nests like this");
}

// ASCII FBX: braces outside quoted strings; comments run from ';' to the end
// of the line.
void check_ascii_fbx_depth(const std::string& path, const std::string& text) {
  int depth = 0;
  bool quoted = false, comment = false;
  for (char c : text) {
    if (comment) {
      comment = c != '\n';
    } else if (quoted) {
      quoted = c != '"';
    } else if (c == '"') {
      quoted = true;
    } else if (c == ';') {
      comment = true;
    } else if (c == '{' && ++depth > kMaxFbxDepth) {
      refuse_deep_fbx(path, kMaxFbxDepth);
    } else if (c == '}' && depth > 0) {
      --depth;
    }
  }
}

// Binary FBX: each record holds its end offset, its properties' length and
// its name, then nested records up to the end offset. Walked with an explicit
// stack; whatever does not parse is left to assimp to report.
void check_binary_fbx_depth(const std::string& path, const std::string& bytes) {
  constexpr size_t kMagic = 23, kVersionAt = 23;
  if (bytes.size() < kMagic + 4) return;
  uint32_t version = 0;
  std::memcpy(&version, bytes.data() + kVersionAt, 4);
  const bool wide = version >= 7500;  // 64-bit offsets from FBX 7.5
  const size_t word = wide ? 8 : 4, header = 3 * word + 1;
  const auto read = [&](size_t at) {
    uint64_t v = 0;
    std::memcpy(&v, bytes.data() + at, word);  // little endian, as FBX
    return v;
  };
  struct Scope {
    size_t at, end;
    int depth;
  };
  std::vector<Scope> stack = {{kMagic + 4, bytes.size(), 0}};
  while (!stack.empty()) {
    Scope s = stack.back();
    stack.pop_back();
    while (s.at + header <= s.end) {
      const uint64_t end = read(s.at), properties = read(s.at + 2 * word);
      const size_t name = static_cast<unsigned char>(bytes[s.at + 3 * word]);
      if (end == 0) break;  // the null record that closes a list
      if (end <= s.at || end > s.end) return;
      const uint64_t nested = s.at + header + name + properties;
      if (nested < end) {
        if (s.depth + 1 > kMaxFbxDepth) refuse_deep_fbx(path, kMaxFbxDepth);
        stack.push_back({static_cast<size_t>(nested), static_cast<size_t>(end), s.depth + 1});
      }
      s.at = static_cast<size_t>(end);
    }
  }
}

void check_fbx_depth(const std::string& path, std::ifstream& in) {
  in.clear();
  in.seekg(0);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (bytes.rfind("Kaydara FBX Binary", 0) == 0)
    check_binary_fbx_depth(path, bytes);
  else
    check_ascii_fbx_depth(path, bytes);
}

}  // namespace

void check_assimp_input(const std::string& path) {
  std::ifstream probe(path, std::ios::binary);
  if (!probe) fail(PLEAT_ERROR_IO, path + ": cannot open the file");
  if (std::filesystem::is_directory(path)) fail(PLEAT_ERROR_IO, path + ": is a directory");
  check_binary_gltf_header(path, probe);
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".fbx") check_fbx_depth(path, probe);
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
