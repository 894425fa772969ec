#pragma once
// Body penetration rate (docs/metrics.md): the percentage of garment vertices
// inside the body, per frame and then averaged over frames. A vertex is
// inside when it lies behind the normal of its nearest body vertex:
// (x - b) . n_b < 0, with n_b the body's area-weighted vertex normal. It is
// the test SNUG's collision loss and pleat's body-collision post-pass use,
// measured with the exact nearest vertex of the posed body.
#include <cstdint>

namespace pleat {

// garment: frames x n x 3; body and body_normals: frames x nb x 3 (metres,
// normals of unit length). Throws PLEAT_ERROR_INVALID_ARGUMENT for empty
// input or a non-finite coordinate (frame and vertex named).
double body_penetration_percent(const float* garment, int64_t n, const float* body, const float* body_normals,
                                int64_t nb, int64_t frames);

}  // namespace pleat
