#pragma once
// Error metrics of predicted against ground-truth garment frames (paper
// section IV, DESIGN section 7). One implementation serves the C API, the
// tests, the bench and the trainer's validation.
//
// Every metric is a mean over all frames and all elements that count:
//   E_verts  vertex distance, cm (positions are metres)                 all vertices
//   E_vnorm  angle between area-weighted vertex normals, degrees        vertices whose
//            normal is non-zero in both meshes (isolated or fully degenerate ones skip)
//   E_fnorm  angle between face normals, degrees                        faces with a
//            positive area in both meshes (degenerate faces have no normal)
//   E_edge   |l_pred - l_true| / l_true, percent                        unique edges
//            with l_true > 0
//   E_curv   |K_pred - K_true|, 1/m^2 (see curvature.h)                 interior vertices
//            with a positive dual area in both meshes; boundary vertices are left out
//   E_low/mid/high  vertex distance of each band of (pred - truth), cm  all vertices
//   self-collision  percent of predicted faces crossed by a non-adjacent edge, per frame
//            and then averaged over frames (see self_collision.h)
// A mean over no elements is 0. Angles come from atan2(|a x b|, a.b), which is
// exact near 0 degrees where acos of a clamped cosine loses precision.
#include <cstddef>
#include <cstdint>
#include <functional>

#include "capi/pleat.h"
#include "core/mesh.h"

namespace pleat {

// Projects tightly packed frames (vertex_count * 3 floats each) onto the low,
// mid and high bands, as src/spectral's split_bands does. It must be linear:
// the metric applies it to the error pred - truth.
using BandSplitFn = std::function<void(const float* in, size_t frames, float* low, float* mid, float* high)>;

struct MetricsOptions {
  uint32_t flags = 0;                  // PLEAT_METRIC_*; 0 = everything that applies
  double collision_prefilter = 0.015;  // metres
};

// Mirrors pleat_metrics: metrics not computed are 0 and their bit is clear.
struct MetricsResult {
  uint32_t computed = 0;
  uint64_t frame_count = 0;
  double e_verts_cm = 0.0;
  double e_vnorm_deg = 0.0;
  double e_fnorm_deg = 0.0;
  double e_edge_percent = 0.0;
  double e_curv = 0.0;
  double e_low_cm = 0.0;
  double e_mid_cm = 0.0;
  double e_high_cm = 0.0;
  double self_collision_percent = 0.0;
  // Not from compute_metrics (it needs the body): body_penetration.h, filled
  // by callers that have the posed body (the trainer's reports, the bench).
  double body_penetration_percent = 0.0;
};

constexpr uint32_t kAllMetrics = PLEAT_METRIC_VERTEX | PLEAT_METRIC_NORMALS | PLEAT_METRIC_EDGES |
                                 PLEAT_METRIC_CURVATURE | PLEAT_METRIC_BANDS | PLEAT_METRIC_SELF_COLLISION;

// Frame f of predicted starts at predicted + f * pred_stride (floats; 0 =
// vertex_count * 3), likewise truth. With flags 0 the band errors are computed
// only when band_split is given; asking for PLEAT_METRIC_BANDS without it
// throws PLEAT_ERROR_NOT_PREPARED. Bad input (no frames, unknown flag bits, a
// stride below vertex_count * 3, a triangle index out of range, NaN/Inf
// coordinates named by frame and vertex, a negative pre-filter radius) throws
// PLEAT_ERROR_INVALID_ARGUMENT.
MetricsResult compute_metrics(const Triangles& triangles, int32_t vertex_count, const float* predicted,
                              size_t pred_stride, const float* truth, size_t truth_stride, size_t frame_count,
                              const MetricsOptions& options, const BandSplitFn* band_split);

}  // namespace pleat
