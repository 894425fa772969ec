// Garment building: welding, topology census, validation of bad meshes, and
// geodesic neighbourhoods, on hand-checkable cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/geodesic.h"
#include "core/topology.h"
#include "core/weld.h"
#include "garment/garment.h"
#include "support/test_support.h"

using namespace pleat;

namespace {

Points3d to_points(const pleat_test::SimpleMesh& m) {
  return Eigen::Map<const Points3f>(m.positions.data(), static_cast<Eigen::Index>(m.vertex_count()), 3)
      .cast<double>();
}
Triangles to_triangles(const pleat_test::SimpleMesh& m) {
  Triangles t(static_cast<Eigen::Index>(m.triangle_count()), 3);
  for (size_t i = 0; i < m.triangles.size(); ++i) t.data()[i] = static_cast<int32_t>(m.triangles[i]);
  return t;
}

// Expects build_garment to fail with `status` and a message containing `text`.
void expect_failure(const Points3d& v, const Triangles& t, pleat_status status, const std::string& text) {
  try {
    build_garment(v, t, {}, "test mesh");
    FAIL() << "expected failure containing '" << text << "'";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), status) << e.what();
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("test mesh"), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(Weld, MergesSeamDuplicatesOnly) {
  // Two triangles of a unit square, each with its own copy of the diagonal.
  Points3d v(6, 3);
  v << 0, 0, 0, 1, 0, 0, 1, 1, 0,  //
      0, 0, 0, 1, 1, 0, 0, 1, 0;
  WeldResult w = weld_vertices(v, 1e-9);
  EXPECT_EQ(w.vertices.rows(), 4);
  EXPECT_EQ(w.merged_count, 2);
  EXPECT_EQ(w.remap[3], w.remap[0]);
  EXPECT_EQ(w.remap[4], w.remap[2]);
  EXPECT_NE(w.remap[5], w.remap[1]);
  EXPECT_EQ(weld_vertices(v, -1.0).vertices.rows(), 6);
}

TEST(Weld, ToleranceIsEuclidean) {
  Points3d v(3, 3);
  v << 0, 0, 0, 0.9e-3, 0, 0, 0.8e-3, 0.8e-3, 0;  // 0.9 mm and 1.13 mm from the first
  EXPECT_EQ(weld_vertices(v, 1e-3).vertices.rows(), 2);
}

TEST(Topology, CensusOfKnownShapes) {
  auto grid = pleat_test::grid(4, 3, 1.0f);
  EdgeCensus c = census_edges(to_triangles(grid), 12);
  EXPECT_EQ(c.boundary_loops, 1);
  EXPECT_EQ(c.boundary_edges, 2 * 3 + 2 * 2);
  EXPECT_EQ(c.non_manifold_edges, 0);

  auto sphere = pleat_test::icosphere(1, 1.0f);
  EdgeCensus s = census_edges(to_triangles(sphere), static_cast<int32_t>(sphere.vertex_count()));
  EXPECT_EQ(s.boundary_loops, 0);
  EXPECT_EQ(s.boundary_edges, 0);

  Triangles fan(3, 3);  // three triangles on the edge (0,1)
  fan << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  EXPECT_EQ(census_edges(fan, 5).non_manifold_edges, 1);

  // Annulus: a 3x3 grid of quads without the centre one has two loops.
  Triangles ring(16, 3);
  int k = 0;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      if (i == 1 && j == 1) continue;
      int a = j * 4 + i;
      ring.row(k++) << a, a + 1, a + 5;
      ring.row(k++) << a, a + 5, a + 4;
    }
  EXPECT_EQ(census_edges(ring, 16).boundary_loops, 2);
}

TEST(Topology, ComponentsAndGraph) {
  auto two = pleat_test::concat(pleat_test::grid(3, 3, 1.0f), pleat_test::grid(2, 2, 1.0f, {5, 0, 0}));
  Csr g = edge_graph(unique_edges(to_triangles(two)), 13);
  std::vector<int32_t> labels;
  EXPECT_EQ(connected_components(g, &labels), 2);
  EXPECT_EQ(labels[0], 0);
  EXPECT_EQ(labels[12], 1);
  // Centre of the 3x3 grid: 4 axis neighbours + 2 diagonals of the split quads.
  EXPECT_EQ(g.degree(4), 6);
}

TEST(GarmentBuild, ReportOfACleanGrid) {
  auto m = pleat_test::grid(5, 4, 0.1f);
  Garment g = build_garment(to_points(m), to_triangles(m), {}, "grid");
  const MeshReport& r = g.report;
  EXPECT_EQ(r.vertex_count, 20u);
  EXPECT_EQ(r.triangle_count, 24u);
  EXPECT_EQ(r.component_count, 1u);
  EXPECT_EQ(r.boundary_loop_count, 1u);
  EXPECT_EQ(r.welded_vertex_count, 0u);
  EXPECT_EQ(r.units, static_cast<uint32_t>(PLEAT_UNITS_METRES));
  EXPECT_NEAR(r.total_area, 0.4 * 0.3, 1e-7);  // float grid spacing
  EXPECT_NEAR(g.rest_normals(7, 2), 1.0, 1e-12);
}

TEST(GarmentBuild, CountsDuplicatesIsolatedAndDegenerate) {
  Points3d v(7, 3);
  v << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,  // square
      1, 1, 0,                              // duplicate of vertex 2
      5, 5, 5,                              // isolated
      2, 0, 0;                              // used only by a degenerate triangle
  Triangles t(3, 3);
  t << 0, 1, 2, 0, 4, 3, 1, 6, 6;
  Garment g = build_garment(v, t, {}, "soup");
  EXPECT_EQ(g.report.welded_vertex_count, 1u);
  EXPECT_EQ(g.report.vertex_count, 6u);
  EXPECT_EQ(g.report.degenerate_triangle_count, 1u);
  EXPECT_EQ(g.report.triangle_count, 2u);
  EXPECT_EQ(g.report.isolated_vertex_count, 2u);
  EXPECT_EQ(g.report.component_count, 3u);
  EXPECT_TRUE(g.rest_normals.allFinite());
}

TEST(GarmentBuild, GuessesCentimetresAndMillimetres) {
  auto m = pleat_test::grid(3, 3, 60.0f);  // 120 units across: a garment in cm
  EXPECT_EQ(build_garment(to_points(m), to_triangles(m), {}, "cm").report.units,
            static_cast<uint32_t>(PLEAT_UNITS_LOOK_LIKE_CENTIMETRES));
  auto mm = pleat_test::grid(3, 3, 600.0f);
  EXPECT_EQ(build_garment(to_points(mm), to_triangles(mm), {}, "mm").report.units,
            static_cast<uint32_t>(PLEAT_UNITS_LOOK_LIKE_MILLIMETRES));
  GarmentBuildOptions scaled;
  scaled.unit_scale = 0.01;
  EXPECT_EQ(build_garment(to_points(m), to_triangles(m), scaled, "cm").report.units,
            static_cast<uint32_t>(PLEAT_UNITS_METRES));
}

TEST(GarmentBuild, RefusesUnusableMeshesWithNamedCause) {
  auto m = pleat_test::grid(3, 3, 0.1f);
  Points3d v = to_points(m);
  Triangles t = to_triangles(m);
  expect_failure(Points3d(0, 3), t, PLEAT_ERROR_INVALID_MESH, "no vertices");
  expect_failure(v, Triangles(0, 3), PLEAT_ERROR_INVALID_MESH, "no triangles");

  Points3d nan = v;
  nan(4, 1) = std::numeric_limits<double>::quiet_NaN();
  expect_failure(nan, t, PLEAT_ERROR_INVALID_MESH, "vertex 4 has a non-finite y");

  Points3d huge = v;
  huge(2, 0) = 1e30;
  expect_failure(huge, t, PLEAT_ERROR_INVALID_MESH, "vertex 2 x coordinate");

  Triangles bad = t;
  bad(3, 2) = 99;
  expect_failure(v, bad, PLEAT_ERROR_INVALID_MESH, "triangle 3 corner 2 references vertex 99");

  Triangles flat(2, 3);
  flat << 0, 0, 1, 0, 1, 2;  // a repeated index; a collinear triple
  expect_failure(v, flat, PLEAT_ERROR_INVALID_MESH, "all 2 triangles are degenerate");
}

TEST(Geodesic, HandComputedNeighbourhood) {
  // 3 x 2 unit grid: from vertex 0, vertices 1 and 3 are 1 away, vertex 4 is
  // sqrt(2) along the diagonal edge, 2 and 5 are at least 2 away.
  auto m = pleat_test::grid(3, 2, 1.0f);
  Points3d v = to_points(m);
  Csr g = edge_graph(unique_edges(to_triangles(m)), 6);
  Csr n = geodesic_neighbourhoods(v, g, 1.5);
  std::vector<int32_t> of0(n.indices.begin() + n.offsets[0], n.indices.begin() + n.offsets[1]);
  EXPECT_EQ(of0, (std::vector<int32_t>{1, 3, 4}));
  // Symmetric relation.
  for (int32_t a = 0; a < 6; ++a)
    for (int32_t k = n.offsets[a]; k < n.offsets[a + 1]; ++k) {
      int32_t b = n.indices[k];
      auto begin = n.indices.begin() + n.offsets[b], end = n.indices.begin() + n.offsets[b + 1];
      EXPECT_TRUE(std::find(begin, end, a) != end) << a << " -> " << b;
    }
  EXPECT_EQ(geodesic_neighbourhoods(v, g, 0.5).indices.size(), 0u);
}
