#pragma once
// Small meshes and paths shared by the tests. Header-only types; no pleat
// internals, so C API tests can use it too.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace pleat_test {

struct SimpleMesh {
  std::vector<float> positions;     // xyz per vertex
  std::vector<uint32_t> triangles;  // three indices per triangle
  size_t vertex_count() const { return positions.size() / 3; }
  size_t triangle_count() const { return triangles.size() / 3; }
};

// nx * ny vertices on the XY plane with the given spacing, origin at `origin`.
SimpleMesh grid(int nx, int ny, float spacing, Eigen::Vector3f origin = Eigen::Vector3f::Zero());

// Appends b to a (indices shifted).
SimpleMesh concat(const SimpleMesh& a, const SimpleMesh& b);

// Mirror image of m across the plane x = 0 (winding flipped).
SimpleMesh mirrored_x(const SimpleMesh& m);

// Subdivided icosahedron projected onto a sphere of the given radius.
SimpleMesh icosphere(int subdivisions, float radius);

// Unit area-weighted vertex normals of n vertices (xyz floats at x): an
// independent reference for the library's.
std::vector<Eigen::Vector3f> area_weighted_normals(const float* x, size_t n,
                                                   const std::vector<uint32_t>& triangles);

// A pleat datagen config: a skirt on `shapes` (a JSON array) in 12 frames
// of 02_02 (3 rest and 6 blend frames before), written to dir/set. It keeps
// the clip's reference pose as frame 0, as the tests were written, so the
// body speed limit is raised past that jump (check.max_body_speed 40 m/s);
// `sequences` is its JSON object of counts per split, `settings` (JSON
// members with a trailing comma) go in first.
std::string skirt_datagen_config(const std::string& dir, const std::string& settings,
                                 const std::string& shapes, const std::string& sequences);

// Repository root (PLEAT_SOURCE_DIR from CTest), the asset pack with bodies
// and motions (PLEAT_ASSET_DIR, by default ../shared/data beside the
// repository), and a fresh temp folder.
std::string source_dir();
std::string asset_dir();
std::string temp_dir(const std::string& name);

// Runs a shell command; returns its exit status and fills *output with stdout.
int run_command(const std::string& command, std::string* output);

}  // namespace pleat_test
