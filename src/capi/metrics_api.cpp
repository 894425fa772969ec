// C entry point for the paper's metrics over a sequence.
#include <cmath>

#include "capi/firewall.h"
#include "capi/handles.h"
#include "metrics/metrics.h"
#include "spectral/band_split.h"

using namespace pleat;
using namespace pleat::capi;

extern "C" {

pleat_status pleat_metrics_compute(const pleat_garment* garment, pleat_const_frames predicted,
                                   pleat_const_frames truth, size_t frame_count,
                                   const pleat_metrics_options* options, pleat_metrics* out_metrics) {
  return guarded(__func__, [&] {
    require_not_null(garment, "garment");
    require_not_null(out_metrics, "out_metrics");
    require_not_null(predicted.data, "predicted.data");
    require_not_null(truth.data, "truth.data");
    pleat_metrics_options o = read_options(options, "pleat_metrics_options");
    PLEAT_REQUIRE(std::isfinite(o.collision_prefilter),
                  "'pleat_metrics_options.collision_prefilter' is not finite");
    MetricsOptions m;
    m.flags = o.flags;
    if (o.collision_prefilter != 0.0) m.collision_prefilter = o.collision_prefilter;

    const Garment& g = *garment->garment;
    BandSplitFn split;
    if (g.prepared) {
      const size_t stride = static_cast<size_t>(g.rest.vertex_count()) * 3;
      split = [&g, stride](const float* in, size_t frames, float* low, float* mid, float* high) {
        split_bands(g.prepared->bands, in, frames, stride, low, stride, mid, stride, high, stride);
      };
    }
    MetricsResult r =
        compute_metrics(g.rest.triangles, g.rest.vertex_count(), predicted.data, predicted.frame_stride,
                        truth.data, truth.frame_stride, frame_count, m, g.prepared ? &split : nullptr);
    pleat_metrics out{};
    out.struct_size = sizeof out;
    out.computed = r.computed;
    out.frame_count = r.frame_count;
    out.e_verts_cm = r.e_verts_cm;
    out.e_vnorm_deg = r.e_vnorm_deg;
    out.e_fnorm_deg = r.e_fnorm_deg;
    out.e_edge_percent = r.e_edge_percent;
    out.e_curv = r.e_curv;
    out.e_low_cm = r.e_low_cm;
    out.e_mid_cm = r.e_mid_cm;
    out.e_high_cm = r.e_high_cm;
    out.self_collision_percent = r.self_collision_percent;
    write_result(out, out_metrics, "out_metrics");
  });
}

}  // extern "C"
