#include "metrics/metrics.h"

#include <Eigen/Geometry>  // cross products
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/geometry.h"
#include "core/topology.h"
#include "metrics/curvature.h"
#include "metrics/self_collision.h"

namespace pleat {
namespace {

constexpr double kCentimetres = 100.0;
constexpr double kDegrees = 180.0 / 3.14159265358979323846;
// Floats per buffer when frames go through the band split in chunks: bounds
// the scratch memory (4 buffers of 4 MB) however long the sequence.
constexpr size_t kBandChunkFloats = size_t{1} << 20;

struct Mean {
  double sum = 0.0;
  uint64_t count = 0;
  void add(double value) {
    sum += value;
    ++count;
  }
  double value() const { return count > 0 ? sum / static_cast<double>(count) : 0.0; }
};

double angle_between(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

Points3d to_points(const float* xyz, int32_t vertex_count) {
  return Eigen::Map<const Points3f>(xyz, vertex_count, 3).cast<double>();
}

void check_finite(const char* which, const float* frames, size_t stride, size_t frame_count,
                  int32_t vertex_count) {
  for (size_t f = 0; f < frame_count; ++f)
    for (size_t i = 0; i < 3 * static_cast<size_t>(vertex_count); ++i)
      if (!std::isfinite(frames[f * stride + i]))
        fail(PLEAT_ERROR_INVALID_ARGUMENT, std::string(which) + " frame " + std::to_string(f) + " vertex " +
                                               std::to_string(i / 3) + " is not finite");
}

size_t checked_stride(const char* which, size_t stride, int32_t vertex_count) {
  size_t packed = 3 * static_cast<size_t>(vertex_count);
  if (stride == 0) return packed;
  if (stride < packed)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, std::string(which) + " frame stride " + std::to_string(stride) +
                                           " is below vertex_count * 3 = " + std::to_string(packed));
  return stride;
}

uint32_t resolve_flags(uint32_t flags, bool have_band_split) {
  if (flags & ~kAllMetrics)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "unknown metric flags " + std::to_string(flags & ~kAllMetrics));
  if (flags == 0) return have_band_split ? kAllMetrics : kAllMetrics & ~PLEAT_METRIC_BANDS;
  if ((flags & PLEAT_METRIC_BANDS) && !have_band_split)
    fail(PLEAT_ERROR_NOT_PREPARED, "band errors need the band projection of a prepared garment");
  return flags;
}

void add_normal_errors(const Points3d& p, const Points3d& t, const Triangles& tri, Mean* vnorm, Mean* fnorm) {
  Points3d pv = vertex_normals(p, tri), tv = vertex_normals(t, tri);
  for (Eigen::Index v = 0; v < pv.rows(); ++v)
    if (!pv.row(v).isZero(0.0) && !tv.row(v).isZero(0.0))
      vnorm->add(kDegrees * angle_between(pv.row(v), tv.row(v)));
  Points3d pf = face_normals(p, tri), tf = face_normals(t, tri);
  for (Eigen::Index f = 0; f < pf.rows(); ++f)
    if (!pf.row(f).isZero(0.0) && !tf.row(f).isZero(0.0))
      fnorm->add(kDegrees * angle_between(pf.row(f), tf.row(f)));
}

void add_edge_errors(const Points3d& p, const Points3d& t, const std::vector<Edge>& edges, Mean* edge) {
  for (const Edge& e : edges) {
    double true_length = (t.row(e.a) - t.row(e.b)).norm();
    if (!(true_length > 0.0)) continue;
    double length = (p.row(e.a) - p.row(e.b)).norm();
    edge->add(100.0 * std::abs(length - true_length) / true_length);
  }
}

void add_curvature_errors(const Points3d& p, const Points3d& t, const Triangles& tri,
                          const std::vector<uint8_t>& interior, Mean* curv) {
  std::vector<uint8_t> p_valid, t_valid;
  Eigen::VectorXd kp = gaussian_curvature(p, tri, interior, &p_valid);
  Eigen::VectorXd kt = gaussian_curvature(t, tri, interior, &t_valid);
  for (Eigen::Index v = 0; v < kp.size(); ++v)
    if (p_valid[v] && t_valid[v]) curv->add(std::abs(kp[v] - kt[v]));
}

// The projection is linear, so the band errors are the bands of the error.
void add_band_errors(const float* pred, size_t pred_stride, const float* truth, size_t truth_stride,
                     size_t frame_count, int32_t vertex_count, const BandSplitFn& split, Mean bands[3]) {
  size_t packed = 3 * static_cast<size_t>(vertex_count);
  size_t chunk = std::max<size_t>(1, std::min(frame_count, kBandChunkFloats / packed));
  std::vector<float> error(chunk * packed), low(error.size()), mid(error.size()), high(error.size());
  float* outputs[3] = {low.data(), mid.data(), high.data()};
  for (size_t first = 0; first < frame_count; first += chunk) {
    size_t count = std::min(chunk, frame_count - first);
    for (size_t f = 0; f < count; ++f)
      for (size_t i = 0; i < packed; ++i)
        error[f * packed + i] = pred[(first + f) * pred_stride + i] - truth[(first + f) * truth_stride + i];
    split(error.data(), count, low.data(), mid.data(), high.data());
    for (int b = 0; b < 3; ++b)
      for (size_t v = 0; v < count * static_cast<size_t>(vertex_count); ++v) {
        const float* d = outputs[b] + 3 * v;
        bands[b].add(kCentimetres *
                     std::sqrt(double{d[0]} * d[0] + double{d[1]} * d[1] + double{d[2]} * d[2]));
      }
  }
}

}  // namespace

MetricsResult compute_metrics(const Triangles& triangles, int32_t vertex_count, const float* predicted,
                              size_t pred_stride, const float* truth, size_t truth_stride, size_t frame_count,
                              const MetricsOptions& options, const BandSplitFn* band_split) {
  uint32_t flags = resolve_flags(options.flags, band_split && *band_split);
  if (frame_count == 0) fail(PLEAT_ERROR_INVALID_ARGUMENT, "metrics need at least one frame");
  if (vertex_count <= 0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "vertex_count is " + std::to_string(vertex_count));
  if (!predicted || !truth) fail(PLEAT_ERROR_INVALID_ARGUMENT, "frame data is NULL");
  if (!(options.collision_prefilter >= 0.0 && std::isfinite(options.collision_prefilter)))
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "collision_prefilter " + std::to_string(options.collision_prefilter) +
                                           " is not a non-negative distance");
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (triangles(f, k) < 0 || triangles(f, k) >= vertex_count)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, "triangle " + std::to_string(f) + " corner " + std::to_string(k) +
                                               ": index " + std::to_string(triangles(f, k)) +
                                               " outside [0, " + std::to_string(vertex_count) + ")");
  pred_stride = checked_stride("predicted", pred_stride, vertex_count);
  truth_stride = checked_stride("truth", truth_stride, vertex_count);
  check_finite("predicted", predicted, pred_stride, frame_count, vertex_count);
  check_finite("truth", truth, truth_stride, frame_count, vertex_count);

  // Topology is shared by every frame: derive it once.
  std::vector<Edge> edges;
  if (flags & (PLEAT_METRIC_EDGES | PLEAT_METRIC_SELF_COLLISION)) edges = unique_edges(triangles);
  std::vector<uint8_t> interior;
  if (flags & PLEAT_METRIC_CURVATURE) interior = interior_vertex_mask(triangles, vertex_count);

  Mean verts, vnorm, fnorm, edge, curv, collision, bands[3];
  for (size_t f = 0; f < frame_count; ++f) {
    Points3d p = to_points(predicted + f * pred_stride, vertex_count);
    Points3d t = to_points(truth + f * truth_stride, vertex_count);
    if (flags & PLEAT_METRIC_VERTEX)
      for (Eigen::Index v = 0; v < p.rows(); ++v) verts.add(kCentimetres * (p.row(v) - t.row(v)).norm());
    if (flags & PLEAT_METRIC_NORMALS) add_normal_errors(p, t, triangles, &vnorm, &fnorm);
    if (flags & PLEAT_METRIC_EDGES) add_edge_errors(p, t, edges, &edge);
    if (flags & PLEAT_METRIC_CURVATURE) add_curvature_errors(p, t, triangles, interior, &curv);
    if ((flags & PLEAT_METRIC_SELF_COLLISION) && triangles.rows() > 0) {
      std::vector<uint8_t> hit = self_intersected_faces(p, triangles, edges, options.collision_prefilter);
      collision.add(100.0 * static_cast<double>(std::count(hit.begin(), hit.end(), 1)) /
                    static_cast<double>(triangles.rows()));
    }
  }
  if (flags & PLEAT_METRIC_BANDS)
    add_band_errors(predicted, pred_stride, truth, truth_stride, frame_count, vertex_count, *band_split,
                    bands);

  MetricsResult result;
  result.computed = flags;
  result.frame_count = frame_count;
  result.e_verts_cm = verts.value();
  result.e_vnorm_deg = vnorm.value();
  result.e_fnorm_deg = fnorm.value();
  result.e_edge_percent = edge.value();
  result.e_curv = curv.value();
  result.e_low_cm = bands[0].value();
  result.e_mid_cm = bands[1].value();
  result.e_high_cm = bands[2].value();
  result.self_collision_percent = collision.value();
  // Finite inputs can still overflow (coordinates near FLT_MAX) and the band
  // split is the caller's code: never hand out a NaN or Inf.
  const double values[] = {result.e_verts_cm,     result.e_vnorm_deg, result.e_fnorm_deg,
                           result.e_edge_percent, result.e_curv,      result.e_low_cm,
                           result.e_mid_cm,       result.e_high_cm,   result.self_collision_percent};
  const char* names[] = {
      "E_verts", "E_vnorm", "E_fnorm", "E_edge", "E_curv", "E_low", "E_mid", "E_high", "self-collision rate"};
  for (int i = 0; i < 9; ++i)
    if (!std::isfinite(values[i]))
      fail(PLEAT_ERROR_NUMERICAL, std::string(names[i]) + " is not finite (coordinates too large?)");
  return result;
}

}  // namespace pleat
