#pragma once
// The triangle mesh and graph types shared by every module.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace pleat {

// N x 3 row-major: one vertex per row, rows contiguous like the C API's xyz.
template <typename Scalar>
using Points = Eigen::Matrix<Scalar, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Points3d = Points<double>;
using Points3f = Points<float>;
using Triangles = Eigen::Matrix<int32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

struct TriMesh {
  Points3d vertices;
  Triangles triangles;
  int32_t vertex_count() const { return static_cast<int32_t>(vertices.rows()); }
  int32_t triangle_count() const { return static_cast<int32_t>(triangles.rows()); }
};

// Compressed sparse rows of a vertex graph: neighbours of v are
// indices[offsets[v] .. offsets[v+1]), sorted ascending, no self loops.
struct Csr {
  std::vector<int32_t> offsets{0};
  std::vector<int32_t> indices;
  int32_t vertex_count() const { return static_cast<int32_t>(offsets.size()) - 1; }
  int32_t degree(int32_t v) const { return offsets[v + 1] - offsets[v]; }
};

// Unique undirected edge (a < b).
struct Edge {
  int32_t a;
  int32_t b;
  bool operator==(const Edge& o) const { return a == o.a && b == o.b; }
  bool operator<(const Edge& o) const { return a < o.a || (a == o.a && b < o.b); }
};

}  // namespace pleat
