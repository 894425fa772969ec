#include "garment_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/geometry.h"
#include "core/nearest_points.h"

namespace pleat::datagen {

CheckReport check_simulation(const std::vector<float>& garment, const Points3d& garment_rest,
                             const std::vector<float>& body, const Points3d& body_rest,
                             const Triangles& body_triangles, int64_t frame_count, double frame_rate,
                             const CheckSettings& settings) {
  CheckReport r;
  const int64_t garment_vertices = garment_rest.rows(), body_vertices = body_rest.rows();
  // Where each garment vertex sits on the body at rest. A vertex that ends up
  // much further from that body vertex than it started has been left behind
  // by the body: a skirt swings by less than slip_distance, a sleeve the arm
  // went through stays where the arm was.
  const std::vector<int32_t> anchor = nearest_points(body_rest, garment_rest);
  std::vector<double> rest_gap(static_cast<size_t>(garment_vertices));
  for (int64_t v = 0; v < garment_vertices; ++v)
    rest_gap[static_cast<size_t>(v)] =
        (garment_rest.row(v) - body_rest.row(anchor[static_cast<size_t>(v)])).norm();
  int64_t worst_slip_frame = 0;
  const auto fail_with = [&](const std::string& why) {
    if (r.passed) r.reason = why;
    r.passed = false;
  };
  for (int64_t f = 0; f < frame_count; ++f) {
    const float* g = garment.data() + f * garment_vertices * 3;
    for (int64_t i = 0; i < garment_vertices * 3; ++i)
      if (!std::isfinite(g[i])) {
        fail_with("frame " + std::to_string(f) + ", vertex " + std::to_string(i / 3) + " is not finite");
        return r;
      }
    const Points3d b =
        Eigen::Map<const Points3f>(body.data() + f * body_vertices * 3, body_vertices, 3).cast<double>();
    if (f > 0) {
      const Eigen::Map<const Points3f> before(body.data() + (f - 1) * body_vertices * 3, body_vertices, 3);
      Eigen::Index fastest = 0;
      const double speed =
          std::sqrt((b.cast<float>() - before).rowwise().squaredNorm().maxCoeff(&fastest)) * frame_rate;
      r.max_body_speed = std::max(r.max_body_speed, speed);
      if (speed > settings.max_body_speed) {
        char why[256];
        std::snprintf(why, sizeof why,
                      "frame %lld: body vertex %lld moves at %.1f m/s (limit %.1f): the clip jumps there (a "
                      "reference pose as its first frame? skip_frames)",
                      static_cast<long long>(f), static_cast<long long>(fastest), speed,
                      settings.max_body_speed);
        fail_with(why);
      }
    }
    const Points3d x = Eigen::Map<const Points3f>(g, garment_vertices, 3).cast<double>();
    const Points3d normals = vertex_normals(b, body_triangles);
    const std::vector<int32_t> nearest = nearest_points(b, x);
    int64_t deep = 0, slipped = 0;
    for (int64_t v = 0; v < garment_vertices; ++v) {
      const int32_t a = anchor[static_cast<size_t>(v)];
      slipped += (x.row(v) - b.row(a)).norm() - rest_gap[static_cast<size_t>(v)] > settings.slip_distance;
      const Eigen::RowVector3d d = x.row(v) - b.row(nearest[static_cast<size_t>(v)]);
      const double distance = d.norm();
      if (distance > r.max_distance) {
        r.max_distance = distance;
        r.max_distance_frame = f;
      }
      if (distance > settings.max_distance)
        fail_with("frame " + std::to_string(f) + ", vertex " + std::to_string(v) + " is " +
                  std::to_string(distance) + " m from the body (limit " +
                  std::to_string(settings.max_distance) + ")");
      if (d.dot(normals.row(nearest[static_cast<size_t>(v)])) < -settings.max_penetration) ++deep;
    }
    const double slip = double(slipped) / double(garment_vertices);
    r.mean_slipped_fraction += slip / double(frame_count);
    if (slip > r.max_slipped_fraction) {
      r.max_slipped_fraction = slip;
      worst_slip_frame = f;
    }
    const double fraction = double(deep) / double(garment_vertices);
    r.mean_penetrating_fraction += fraction / double(frame_count);
    r.max_penetrating_fraction = std::max(r.max_penetrating_fraction, fraction);
    if (fraction > settings.max_penetrating_fraction)
      fail_with("frame " + std::to_string(f) + ": " + std::to_string(deep) + " vertices are more than " +
                std::to_string(settings.max_penetration) + " m inside the body (limit " +
                std::to_string(settings.max_penetrating_fraction * 100) + "% of vertices)");
  }
  if (r.mean_slipped_fraction > settings.max_slipped_fraction) {
    char why[256];
    std::snprintf(why, sizeof why,
                  "%.1f %% of the vertices are, on average over the frames, more than %.2f m further from "
                  "the body vertex they sat at than at rest (limit %.1f %%; worst frame %lld: %.1f %%): the "
                  "body came out of the garment",
                  100 * r.mean_slipped_fraction, settings.slip_distance, 100 * settings.max_slipped_fraction,
                  static_cast<long long>(worst_slip_frame), 100 * r.max_slipped_fraction);
    fail_with(why);
  }
  return r;
}

}  // namespace pleat::datagen
