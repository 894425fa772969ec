#include "garment_check.h"

#include <cmath>

#include "core/geometry.h"
#include "core/nearest_points.h"

namespace pleat::datagen {

CheckReport check_simulation(const std::vector<float>& garment, int64_t garment_vertices,
                             const std::vector<float>& body, const Triangles& body_triangles,
                             int64_t frame_count, const CheckSettings& settings) {
  CheckReport r;
  const int64_t body_vertices = static_cast<int64_t>(body.size()) / (3 * frame_count);
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
    const Points3d x = Eigen::Map<const Points3f>(g, garment_vertices, 3).cast<double>();
    const Points3d normals = vertex_normals(b, body_triangles);
    const std::vector<int32_t> nearest = nearest_points(b, x);
    int64_t deep = 0;
    for (int64_t v = 0; v < garment_vertices; ++v) {
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
    const double fraction = double(deep) / double(garment_vertices);
    r.mean_penetrating_fraction += fraction / double(frame_count);
    r.max_penetrating_fraction = std::max(r.max_penetrating_fraction, fraction);
    if (fraction > settings.max_penetrating_fraction)
      fail_with("frame " + std::to_string(f) + ": " + std::to_string(deep) + " vertices are more than " +
                std::to_string(settings.max_penetration) + " m inside the body (limit " +
                std::to_string(settings.max_penetrating_fraction * 100) + "% of vertices)");
  }
  return r;
}

}  // namespace pleat::datagen
