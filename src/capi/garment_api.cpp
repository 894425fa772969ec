// C entry points for garments: load, prepare, save, inspect, split bands.
#include <algorithm>
#include <cmath>
#include <memory>

#include "capi/firewall.h"
#include "capi/frames.h"
#include "capi/handles.h"
#include "core/geodesic.h"
#include "garment/garment.h"
#include "garment/garment_file.h"
#include "io/mesh_import.h"
#include "spectral/band_split.h"
#include "spectral/bands.h"

using namespace pleat;
using namespace pleat::capi;

namespace {

GarmentBuildOptions build_options(const pleat_garment_load_options* options) {
  pleat_garment_load_options o = read_options(options, "pleat_garment_load_options");
  PLEAT_REQUIRE(std::isfinite(o.weld_tolerance), "'pleat_garment_load_options.weld_tolerance' is not finite");
  PLEAT_REQUIRE(std::isfinite(o.unit_scale) && o.unit_scale >= 0.0,
                "'pleat_garment_load_options.unit_scale' must be a finite positive number (0 = 1)");
  GarmentBuildOptions b;
  b.weld_tolerance = o.weld_tolerance;
  b.unit_scale = o.unit_scale > 0.0 ? o.unit_scale : 1.0;
  return b;
}

void hand_out(Garment&& garment, pleat_garment** out) {
  *out = new pleat_garment{std::make_shared<const Garment>(std::move(garment))};
}

const PreparedData& prepared(const pleat_garment* g) {
  if (!g->garment->prepared)
    fail(PLEAT_ERROR_NOT_PREPARED,
         "garment '" + g->garment->source + "' is not prepared; call pleat_garment_prepare");
  return *g->garment->prepared;
}

}  // namespace

extern "C" {

pleat_status pleat_garment_load(const char* path, const pleat_garment_load_options* options,
                                pleat_garment** out_garment) {
  return guarded(__func__, [&] {
    require_not_null(path, "path");
    require_not_null(out_garment, "out_garment");
    if (is_garment_file(path)) return hand_out(load_garment_file(path), out_garment);
    GarmentBuildOptions b = build_options(options);
    ImportedMesh mesh = import_mesh(path);
    hand_out(build_garment(mesh.vertices, mesh.triangles, b, path), out_garment);
  });
}

pleat_status pleat_garment_create(const float* positions, size_t vertex_count, const uint32_t* triangles,
                                  size_t triangle_count, const pleat_garment_load_options* options,
                                  pleat_garment** out_garment) {
  return guarded(__func__, [&] {
    require_not_null(positions, "positions");
    require_not_null(triangles, "triangles");
    require_not_null(out_garment, "out_garment");
    PLEAT_REQUIRE(vertex_count < (size_t{1} << 30) && triangle_count < (size_t{1} << 30),
                  "vertex_count or triangle_count exceeds 2^30");
    GarmentBuildOptions b = build_options(options);
    Points3d v =
        Eigen::Map<const Points3f>(positions, static_cast<Eigen::Index>(vertex_count), 3).cast<double>();
    const Triangles t = caller_triangles(triangles, triangle_count, vertex_count, "triangles");
    hand_out(build_garment(v, t, b, "caller arrays"), out_garment);
  });
}

void pleat_garment_destroy(pleat_garment* garment) {
  delete garment;
}

pleat_status pleat_garment_get_report(const pleat_garment* garment, pleat_mesh_report* out_report) {
  return guarded(__func__, [&] {
    require_not_null(garment, "garment");
    const MeshReport& m = garment->garment->report;
    pleat_mesh_report r{};
    r.struct_size = sizeof r;
    r.input_vertex_count = m.input_vertex_count;
    r.vertex_count = m.vertex_count;
    r.triangle_count = m.triangle_count;
    r.welded_vertex_count = m.welded_vertex_count;
    r.component_count = m.component_count;
    r.boundary_loop_count = m.boundary_loop_count;
    r.non_manifold_edge_count = m.non_manifold_edge_count;
    r.degenerate_triangle_count = m.degenerate_triangle_count;
    r.isolated_vertex_count = m.isolated_vertex_count;
    r.units = m.units;
    std::copy_n(m.bbox_min, 3, r.bbox_min);
    std::copy_n(m.bbox_max, 3, r.bbox_max);
    r.total_area = m.total_area;
    write_result(r, out_report, "out_report");
  });
}

pleat_status pleat_garment_get_mesh(const pleat_garment* garment, float* positions, size_t positions_capacity,
                                    uint32_t* triangles, size_t triangles_capacity) {
  return guarded(__func__, [&] {
    require_not_null(garment, "garment");
    const TriMesh& m = garment->garment->rest;
    const auto nv = static_cast<size_t>(m.vertices.size()), nt = static_cast<size_t>(m.triangles.size());
    if (positions && positions_capacity < nv)
      fail(PLEAT_ERROR_BUFFER_TOO_SMALL, "positions_capacity " + std::to_string(positions_capacity) +
                                             " is below the " + std::to_string(nv) + " floats needed");
    if (triangles && triangles_capacity < nt)
      fail(PLEAT_ERROR_BUFFER_TOO_SMALL, "triangles_capacity " + std::to_string(triangles_capacity) +
                                             " is below the " + std::to_string(nt) + " indices needed");
    if (positions) Eigen::Map<Points3f>(positions, m.vertices.rows(), 3) = m.vertices.cast<float>();
    if (triangles)
      std::transform(m.triangles.data(), m.triangles.data() + nt, triangles,
                     [](int32_t i) { return static_cast<uint32_t>(i); });
  });
}

pleat_status pleat_garment_prepare(pleat_garment* garment, const pleat_prepare_options* options) {
  return guarded(__func__, [&] {
    require_not_null(garment, "garment");
    pleat_prepare_options o = read_options(options, "pleat_prepare_options");
    PLEAT_REQUIRE(o.solver <= PLEAT_SOLVER_HYBRID,
                  "'pleat_prepare_options.solver' has unknown value " + std::to_string(o.solver));
    PLEAT_REQUIRE(o.projection <= PLEAT_PROJECTION_SYMMETRIC,
                  "'pleat_prepare_options.projection' has unknown value " + std::to_string(o.projection));
    PLEAT_REQUIRE(std::isfinite(o.geodesic_radius) && o.geodesic_radius >= 0.0,
                  "'pleat_prepare_options.geodesic_radius' must be finite and >= 0");
    BandOptions b;
    if (o.low_fraction != 0.0) b.low_fraction = o.low_fraction;
    if (o.mid_fraction != 0.0) b.mid_fraction = o.mid_fraction;
    b.solver = static_cast<SolverKind>(o.solver);
    b.projection = static_cast<ProjectionForm>(o.projection);
    const Garment& g = *garment->garment;
    auto next = std::make_shared<Garment>(g);
    next->prepared =
        prepare_garment(g, b, o.geodesic_radius > 0.0 ? o.geodesic_radius : kDefaultGeodesicRadius);
    garment->garment = std::move(next);
  });
}

pleat_status pleat_garment_get_band_info(const pleat_garment* garment, pleat_band_info* out_info) {
  return guarded(__func__, [&] {
    require_not_null(garment, "garment");
    const PreparedData& p = prepared(garment);
    pleat_band_info info{};
    info.struct_size = sizeof info;
    info.vertex_count = static_cast<uint32_t>(p.bands.vertex_count);
    info.low_count = static_cast<uint32_t>(p.bands.low_count);
    info.mid_count = static_cast<uint32_t>(p.bands.mid_count);
    info.low_count_requested = static_cast<uint32_t>(p.bands.low_requested);
    info.mid_count_requested = static_cast<uint32_t>(p.bands.mid_requested);
    info.solver = static_cast<uint32_t>(p.bands.solver);
    info.projection = static_cast<uint32_t>(p.bands.projection);
    info.low_gap = p.bands.low_gap;
    info.mid_gap = p.bands.mid_gap;
    info.geodesic_radius = p.geodesic_radius;
    info.geodesic_pair_count = p.geodesic.indices.size();
    write_result(info, out_info, "out_info");
  });
}

pleat_status pleat_garment_save(const pleat_garment* garment, const char* path) {
  return guarded(__func__, [&] {
    require_not_null(garment, "garment");
    require_not_null(path, "path");
    save_garment(*garment->garment, path);
  });
}

pleat_status pleat_garment_split_bands(const pleat_garment* garment, pleat_const_frames positions,
                                       size_t frame_count, pleat_frames low, pleat_frames mid,
                                       pleat_frames high) {
  return guarded(__func__, [&] {
    require_not_null(garment, "garment");
    const PreparedData& p = prepared(garment);
    const auto n = static_cast<size_t>(garment->garment->rest.vertex_count());
    const size_t in_stride = checked_input(positions, "positions", n, frame_count);
    const size_t low_stride = checked_output(low, "low", n);
    const size_t mid_stride = checked_output(mid, "mid", n);
    const size_t high_stride = checked_output(high, "high", n);
    split_bands(p.bands, positions.data, frame_count, in_stride, low.data, low_stride, mid.data, mid_stride,
                high.data, high_stride);
  });
}

}  // extern "C"
