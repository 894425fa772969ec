#pragma once
// Graphs and positions of the test meshes, for the spectral tests.
#include <vector>

#include "core/mesh.h"
#include "core/topology.h"
#include "support/test_support.h"

namespace spectral_test {

// Edge graph of the mesh plus `isolated` vertices used by no triangle.
inline pleat::Csr graph_of(const pleat_test::SimpleMesh& mesh, int isolated = 0) {
  pleat::Triangles t(static_cast<Eigen::Index>(mesh.triangle_count()), 3);
  for (size_t i = 0; i < mesh.triangles.size(); ++i)
    t(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) =
        static_cast<int32_t>(mesh.triangles[i]);
  return pleat::edge_graph(pleat::unique_edges(t), static_cast<int32_t>(mesh.vertex_count()) + isolated);
}

// Positions as doubles, `isolated` extra vertices placed off the mesh.
inline pleat::Points3d positions_of(const pleat_test::SimpleMesh& mesh, int isolated = 0) {
  const auto n = static_cast<Eigen::Index>(mesh.vertex_count());
  pleat::Points3d p(n + isolated, 3);
  for (Eigen::Index v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) p(v, c) = mesh.positions[static_cast<size_t>(3 * v + c)];
  for (Eigen::Index v = n; v < n + isolated; ++v) p.row(v) << 5.0 + v, -2.0, 0.5 * v;
  return p;
}

}  // namespace spectral_test
