#pragma once
// Shared by the libFuzzer targets (fuzz_*.cpp). Loaders that take a path get
// the input as a file in a private folder on tmpfs; pleat::Error is the
// expected answer to bad bytes. Anything else (a foreign exception, a crash,
// a sanitizer report, an invariant below) is a finding: libFuzzer stops and
// keeps the input.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "core/mesh.h"

namespace pleat_fuzz {

// Writes the input to `name` in this process's folder (/dev/shm when there is
// one, else the temp folder) and returns the path.
inline std::string input_file(const uint8_t* data, size_t size, const std::string& name) {
  static const std::filesystem::path folder = [] {
    std::filesystem::path base = std::filesystem::exists("/dev/shm") ? std::filesystem::path("/dev/shm")
                                                                     : std::filesystem::temp_directory_path();
    std::filesystem::path dir = base / ("pleat-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    // Removed at exit; a crashed run leaves it for the next reboot of tmpfs.
    static const std::string to_remove = dir.string();
    std::atexit([] { std::filesystem::remove_all(to_remove); });
    return dir;
  }();
  const std::string path = (folder / name).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), size);
  return path;
}

// Aborts (a finding) when `ok` is false: a loader returned something its
// callers are promised never to get.
inline void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "invariant broken: %s\n", what);
    std::abort();
  }
}

// Every index in range and every coordinate finite: what every mesh loader
// promises the spectral and runtime code downstream.
inline void require_valid_mesh(const pleat::Points3d& vertices, const pleat::Triangles& triangles) {
  require(vertices.allFinite(), "mesh coordinates are finite");
  for (Eigen::Index i = 0; i < triangles.size(); ++i)
    require(triangles.data()[i] >= 0 && triangles.data()[i] < vertices.rows(), "triangle index in range");
}

// Runs load(); swallows pleat::Error, the documented failure.
template <class Load>
int run(Load&& load) {
  try {
    load();
  } catch (const pleat::Error&) {
  }
  return 0;
}

}  // namespace pleat_fuzz
