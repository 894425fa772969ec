#include "metrics/body_penetration.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/nearest_points.h"

namespace pleat {
namespace {

Points3d frame_points(const float* x, int64_t count, int64_t frame, const char* what) {
  Points3d p(count, 3);
  for (int64_t v = 0; v < count; ++v)
    for (int k = 0; k < 3; ++k) {
      const float value = x[3 * v + k];
      if (!std::isfinite(value))
        fail(PLEAT_ERROR_INVALID_ARGUMENT, std::string("body penetration: ") + what + " frame " +
                                               std::to_string(frame) + " vertex " + std::to_string(v) +
                                               " is not finite");
      p(v, k) = value;
    }
  return p;
}

}  // namespace

double body_penetration_percent(const float* garment, int64_t n, const float* body, const float* body_normals,
                                int64_t nb, int64_t frames) {
  if (n <= 0 || nb <= 0 || frames <= 0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "body penetration: " + std::to_string(frames) + " frames of " +
                                           std::to_string(n) + " garment and " + std::to_string(nb) +
                                           " body vertices");
  double sum = 0.0;
  for (int64_t f = 0; f < frames; ++f) {
    const Points3d x = frame_points(garment + f * n * 3, n, f, "garment");
    const Points3d b = frame_points(body + f * nb * 3, nb, f, "body");
    const float* normals = body_normals + f * nb * 3;
    const std::vector<int32_t> nearest = nearest_points(b, x);
    int64_t inside = 0;
    for (int64_t v = 0; v < n; ++v) {
      const int32_t c = nearest[static_cast<size_t>(v)];
      double depth = 0.0;
      for (int k = 0; k < 3; ++k) depth += (x(v, k) - b(c, k)) * normals[3 * c + k];
      inside += depth < 0.0;
    }
    sum += 100.0 * static_cast<double>(inside) / static_cast<double>(n);
  }
  return sum / static_cast<double>(frames);
}

}  // namespace pleat
