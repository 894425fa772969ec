#pragma once
// A garment: the welded rest mesh, its graph and rest geometry, what loading
// found, and (once prepared) its spectral bands and geodesic neighbourhoods.
#include <optional>
#include <string>
#include <vector>

#include "capi/pleat.h"
#include "core/mesh.h"
#include "spectral/bands.h"

namespace pleat {

struct GarmentBuildOptions {
  double weld_tolerance = 0.0;  // 0: relative default; < 0: no welding
  double unit_scale = 1.0;
};

// Relative weld tolerance used when the caller gives none.
constexpr double kDefaultWeldTolerance = 1e-6;  // of the bounding-box diagonal
// Geodesic radius of the self-collision neighbourhoods (paper Eq. 15), metres.
constexpr double kDefaultGeodesicRadius = 0.10;
// Coordinates beyond this many metres are treated as corrupt input.
constexpr double kMaxCoordinate = 1e5;

struct PreparedData {
  BandBasis<float> bands;
  double geodesic_radius = 0.0;
  Csr geodesic;  // rest-pose neighbourhoods within geodesic_radius
};

// What building a garment found in its mesh (the C API copies it into a
// pleat_mesh_report; the fields mean the same).
struct MeshReport {
  uint32_t input_vertex_count = 0;
  uint32_t vertex_count = 0;
  uint32_t triangle_count = 0;
  uint32_t welded_vertex_count = 0;
  uint32_t component_count = 0;
  uint32_t boundary_loop_count = 0;
  uint32_t non_manifold_edge_count = 0;
  uint32_t degenerate_triangle_count = 0;
  uint32_t isolated_vertex_count = 0;
  uint32_t units = 0;  // PLEAT_UNITS_*
  float bbox_min[3] = {0, 0, 0};
  float bbox_max[3] = {0, 0, 0};
  double total_area = 0.0;  // m^2
};

struct Garment {
  TriMesh rest;                        // welded, degenerate triangles dropped
  std::vector<int32_t> source_vertex;  // input vertex -> rest vertex
  std::vector<Edge> edges;
  Csr graph;
  Points3d rest_normals;
  Eigen::VectorXd vertex_areas;
  MeshReport report;
  std::optional<PreparedData> prepared;
  std::string source;  // file it came from, for messages
};

// Validates, welds and analyses a triangle soup. `source` names the origin in
// error messages. Throws PLEAT_ERROR_INVALID_MESH only for unusable input.
Garment build_garment(const Points3d& vertices, const Triangles& triangles,
                      const GarmentBuildOptions& options, const std::string& source);

// Computes the prepared data (band basis with `bands`, geodesic
// neighbourhoods within `geodesic_radius` metres), once per topology.
PreparedData prepare_garment(const Garment& garment, const BandOptions& bands, double geodesic_radius);

// Recomputes the derived rest data (edges, graph, normals, areas) of
// garment.rest; shared by build_garment and the prepared-file reader.
void derive_rest_data(Garment* garment);

}  // namespace pleat
