#include "garment/garment.h"

#include <Eigen/Geometry>
#include <cmath>

#include "core/error.h"
#include "core/geodesic.h"
#include "core/geometry.h"
#include "core/topology.h"
#include "core/weld.h"

namespace pleat {
namespace {

void check_input(const Points3d& vertices, const Triangles& triangles, const std::string& source) {
  if (vertices.rows() == 0) fail(PLEAT_ERROR_INVALID_MESH, source + ": mesh has no vertices");
  if (triangles.rows() == 0) fail(PLEAT_ERROR_INVALID_MESH, source + ": mesh has no triangles");
  static const char* axis[] = {"x", "y", "z"};
  for (Eigen::Index v = 0; v < vertices.rows(); ++v)
    for (int c = 0; c < 3; ++c) {
      double x = vertices(v, c);
      if (!std::isfinite(x))
        fail(PLEAT_ERROR_INVALID_MESH,
             source + ": vertex " + std::to_string(v) + " has a non-finite " + axis[c] + " coordinate");
      if (std::abs(x) > kMaxCoordinate)
        fail(PLEAT_ERROR_INVALID_MESH, source + ": vertex " + std::to_string(v) + " " + axis[c] +
                                           " coordinate " + std::to_string(x) +
                                           " is beyond 1e5 m; check the file's units (unit_scale)");
    }
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      if (triangles(f, c) < 0 || triangles(f, c) >= vertices.rows())
        fail(PLEAT_ERROR_INVALID_MESH, source + ": triangle " + std::to_string(f) + " corner " +
                                           std::to_string(c) + " references vertex " +
                                           std::to_string(triangles(f, c)) + " of " +
                                           std::to_string(vertices.rows()));
}

uint32_t guess_units(double diagonal) {
  // A garment spans a few decimetres to two metres. Ten times that is no
  // longer plausible in metres.
  if (diagonal > 500.0) return PLEAT_UNITS_LOOK_LIKE_MILLIMETRES;
  if (diagonal > 5.0) return PLEAT_UNITS_LOOK_LIKE_CENTIMETRES;
  return PLEAT_UNITS_METRES;
}

}  // namespace

void derive_rest_data(Garment* g) {
  g->edges = unique_edges(g->rest.triangles);
  g->graph = edge_graph(g->edges, g->rest.vertex_count());
  g->rest_normals = vertex_normals(g->rest.vertices, g->rest.triangles);
  g->vertex_areas = vertex_areas(g->rest.vertices, g->rest.triangles);
}

Garment build_garment(const Points3d& input_vertices, const Triangles& input_triangles,
                      const GarmentBuildOptions& options, const std::string& source) {
  check_input(input_vertices, input_triangles, source);
  Points3d scaled = input_vertices * options.unit_scale;
  check_input(scaled, input_triangles, source);

  Garment g;
  g.source = source;
  const Eigen::RowVector3d lo = scaled.colwise().minCoeff(), hi = scaled.colwise().maxCoeff();
  const double diagonal = (hi - lo).norm();
  const double tolerance = options.weld_tolerance > 0.0    ? options.weld_tolerance
                           : options.weld_tolerance == 0.0 ? kDefaultWeldTolerance * diagonal
                                                           : -1.0;
  WeldResult weld = weld_vertices(scaled, tolerance);
  g.rest.vertices = std::move(weld.vertices);
  g.source_vertex = std::move(weld.remap);

  // Drop triangles that collapsed (repeated corner after welding, or zero
  // area): they carry no surface and would give NaN normals downstream.
  std::vector<Eigen::Index> kept;
  int32_t degenerate = 0;
  for (Eigen::Index f = 0; f < input_triangles.rows(); ++f) {
    int32_t a = g.source_vertex[input_triangles(f, 0)], b = g.source_vertex[input_triangles(f, 1)],
            c = g.source_vertex[input_triangles(f, 2)];
    Eigen::RowVector3d pa = g.rest.vertices.row(a), pb = g.rest.vertices.row(b), pc = g.rest.vertices.row(c);
    double twice_area = (pb - pa).cross(pc - pa).norm();
    if (a == b || b == c || a == c || !(twice_area > 1e-12 * diagonal * diagonal)) {
      ++degenerate;
      continue;
    }
    kept.push_back(f);
  }
  if (kept.empty())
    fail(PLEAT_ERROR_INVALID_MESH,
         source + ": all " + std::to_string(input_triangles.rows()) + " triangles are degenerate");
  g.rest.triangles.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (size_t k = 0; k < kept.size(); ++k)
    for (int c = 0; c < 3; ++c)
      g.rest.triangles(static_cast<Eigen::Index>(k), c) = g.source_vertex[input_triangles(kept[k], c)];

  derive_rest_data(&g);

  MeshReport& r = g.report;
  r.input_vertex_count = static_cast<uint32_t>(input_vertices.rows());
  r.vertex_count = static_cast<uint32_t>(g.rest.vertex_count());
  r.triangle_count = static_cast<uint32_t>(g.rest.triangle_count());
  r.welded_vertex_count = static_cast<uint32_t>(weld.merged_count);
  std::vector<int32_t> labels;
  r.component_count = static_cast<uint32_t>(connected_components(g.graph, &labels));
  EdgeCensus census = census_edges(g.rest.triangles, g.rest.vertex_count());
  r.boundary_loop_count = static_cast<uint32_t>(census.boundary_loops);
  r.non_manifold_edge_count = static_cast<uint32_t>(census.non_manifold_edges);
  r.degenerate_triangle_count = static_cast<uint32_t>(degenerate);
  for (int32_t v = 0; v < g.rest.vertex_count(); ++v)
    if (g.graph.degree(v) == 0) ++r.isolated_vertex_count;
  r.units = guess_units(diagonal);
  for (int c = 0; c < 3; ++c) {
    r.bbox_min[c] = static_cast<float>(lo[c]);
    r.bbox_max[c] = static_cast<float>(hi[c]);
  }
  r.total_area = g.vertex_areas.sum();
  return g;
}

PreparedData prepare_garment(const Garment& garment, const BandOptions& bands, double geodesic_radius) {
  PreparedData p;
  p.bands = compute_band_basis(garment.graph, bands).cast<float>();
  p.geodesic_radius = geodesic_radius;
  p.geodesic = geodesic_neighbourhoods(garment.rest.vertices, garment.graph, geodesic_radius);
  return p;
}

}  // namespace pleat
