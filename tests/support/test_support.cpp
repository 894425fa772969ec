#include "support/test_support.h"

#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <stdexcept>

namespace pleat_test {

SimpleMesh grid(int nx, int ny, float spacing, Eigen::Vector3f origin) {
  SimpleMesh m;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      m.positions.push_back(origin.x() + spacing * static_cast<float>(i));
      m.positions.push_back(origin.y() + spacing * static_cast<float>(j));
      m.positions.push_back(origin.z());
    }
  auto id = [nx](int i, int j) { return static_cast<uint32_t>(j * nx + i); };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

SimpleMesh concat(const SimpleMesh& a, const SimpleMesh& b) {
  SimpleMesh m = a;
  auto shift = static_cast<uint32_t>(a.vertex_count());
  m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
  for (uint32_t i : b.triangles) m.triangles.push_back(i + shift);
  return m;
}

SimpleMesh mirrored_x(const SimpleMesh& m) {
  SimpleMesh r = m;
  for (size_t v = 0; v < r.vertex_count(); ++v) r.positions[3 * v] = -r.positions[3 * v];
  for (size_t f = 0; f < r.triangle_count(); ++f) std::swap(r.triangles[3 * f + 1], r.triangles[3 * f + 2]);
  return r;
}

SimpleMesh icosphere(int subdivisions, float radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& p : v) p.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      auto id = static_cast<uint32_t>(v.size() - 1);
      mid[key] = id;
      return id;
    };
    std::vector<std::array<uint32_t, 3>> next;
    for (auto& tri : f) {
      uint32_t a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], a, c});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], c, b});
      next.push_back({a, b, c});
    }
    f.swap(next);
  }
  SimpleMesh m;
  for (auto& p : v)
    for (int k = 0; k < 3; ++k) m.positions.push_back(static_cast<float>(p[k] * radius));
  for (auto& tri : f) m.triangles.insert(m.triangles.end(), tri.begin(), tri.end());
  return m;
}

std::vector<Eigen::Vector3f> area_weighted_normals(const float* x, size_t n,
                                                   const std::vector<uint32_t>& triangles) {
  std::vector<Eigen::Vector3f> normals(n, Eigen::Vector3f::Zero());
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const Eigen::Vector3f a(x + 3 * triangles[t]), b(x + 3 * triangles[t + 1]), c(x + 3 * triangles[t + 2]);
    const Eigen::Vector3f face = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) normals[triangles[t + k]] += face;
  }
  for (Eigen::Vector3f& v : normals) v.normalize();
  return normals;
}

std::string skirt_datagen_config(const std::string& dir, const std::string& settings,
                                 const std::string& shapes, const std::string& sequences) {
  const std::string a = asset_dir();
  return "{" + settings + " \"name\": \"t\", \"body\": \"" + a + "/body\", \"output\": \"" + dir +
         "/set\",\n \"segment_frames\": 12, \"segments_per_clip\": 1, \"mirror\": false, \"rest_frames\": 3,"
         " \"blend_frames\": 6, \"check\": {\"max_body_speed\": 40}, \"sequences\": " +
         sequences + ",\n \"garments\": [{\"name\": \"skirt\", \"mhclo\": \"" + a +
         "/garments/helpers_mhclo/skirthelper.mhclo\"}],\n \"shapes\": " + shapes +
         ",\n \"motions\": [{\"source\": \"" + a + "/motions/cmu_daz/02_02.bvh\", \"map\": \"" +
         source_dir() + "/data/retarget/cmu_daz.txt\"}]}";
}

std::string source_dir() {
  const char* dir = std::getenv("PLEAT_SOURCE_DIR");
  if (!dir) throw std::runtime_error("PLEAT_SOURCE_DIR is not set: run the tests through ctest");
  return dir;
}

std::string asset_dir() {
  const char* dir = std::getenv("PLEAT_ASSET_DIR");
  const std::string path = dir ? dir : source_dir() + "/../shared/data";
  if (!std::filesystem::is_directory(path + "/body"))
    throw std::runtime_error("asset pack not found at '" + path + "' (set PLEAT_ASSET_DIR)");
  return path;
}

std::string temp_dir(const std::string& name) {
  auto dir =
      std::filesystem::temp_directory_path() / ("pleat_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

int run_command(const std::string& command, std::string* output) {
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buffer;
  output->clear();
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) output->append(buffer.data(), n);
  int status = ::pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace pleat_test
