#include "runtime/body_collision.h"

#include <algorithm>
#include <cmath>

#include "core/geometry.h"
#include "core/nearest_points.h"
#include "core/topology.h"

namespace pleat::runtime {

BodyCollision::BodyCollision(const Body& body, const Points3f& garment_rest,
                             const std::vector<int32_t>& model_of_body) {
  const int32_t n = static_cast<int32_t>(garment_rest.rows()), nb = body.vertex_count();
  const Csr ring = edge_graph(unique_edges(body.rest.triangles), nb);
  const std::vector<int32_t> nearest = nearest_points(body.rest.vertices, garment_rest.cast<double>());

  // Body vertices used by any garment vertex get a slot, in first-use order.
  std::vector<int32_t> slot(static_cast<size_t>(nb), -1);
  std::vector<int32_t> used;
  for (int32_t v = 0; v < n; ++v) {
    const int32_t centre = nearest[v];
    for (int32_t k = ring.offsets[centre] - 1; k < ring.offsets[centre + 1]; ++k) {
      const int32_t b = k < ring.offsets[centre] ? centre : ring.indices[k];  // the vertex, then its 1-ring
      if (slot[b] < 0) {
        slot[b] = static_cast<int32_t>(used.size());
        used.push_back(b);
      }
      candidates_.push_back(slot[b]);
    }
    candidate_offsets_.push_back(static_cast<int32_t>(candidates_.size()));
  }
  const Points3d normals = vertex_normals(body.rest.vertices, body.rest.triangles);
  const auto u = static_cast<Eigen::Index>(used.size());
  rest_.resize(u, 3);
  rest_normals_.resize(u, 3);
  posed_.resize(u, 3);
  posed_normals_.resize(u, 3);
  for (Eigen::Index i = 0; i < u; ++i) {
    const int32_t b = used[static_cast<size_t>(i)];
    const Eigen::RowVector3d normal = normals.row(b).normalized();
    for (int k = 0; k < 3; ++k) {
      rest_(i, k) = static_cast<float>(body.rest.vertices(b, k));
      rest_normals_(i, k) = static_cast<float>(normal[k]);
    }
    for (int32_t k = body.weights.offsets[b]; k < body.weights.offsets[b + 1]; ++k) {
      joints_.push_back(model_of_body[static_cast<size_t>(body.weights.joints[k])]);
      weights_.push_back(static_cast<float>(body.weights.weights[k]));
    }
    weight_offsets_.push_back(static_cast<int32_t>(joints_.size()));
  }
}

void BodyCollision::apply(const nn::MatrixRM& skin, float distance, float* positions) {
  for (Eigen::Index i = 0; i < posed_.rows(); ++i) {
    float s[12] = {};
    for (int32_t k = weight_offsets_[i]; k < weight_offsets_[i + 1]; ++k) {
      const float* joint = skin.row(joints_[k]).data();
      for (int c = 0; c < 12; ++c) s[c] += weights_[k] * joint[c];
    }
    const float x = rest_(i, 0), y = rest_(i, 1), z = rest_(i, 2);
    posed_(i, 0) = s[0] * x + s[1] * y + s[2] * z + s[3];
    posed_(i, 1) = s[4] * x + s[5] * y + s[6] * z + s[7];
    posed_(i, 2) = s[8] * x + s[9] * y + s[10] * z + s[11];
    // Normals rotate with the blended matrix's linear part (no inverse
    // transpose: skinning matrices are rotations blended, close to one).
    const float nx = rest_normals_(i, 0), ny = rest_normals_(i, 1), nz = rest_normals_(i, 2);
    const float a = s[0] * nx + s[1] * ny + s[2] * nz, b = s[4] * nx + s[5] * ny + s[6] * nz,
                c = s[8] * nx + s[9] * ny + s[10] * nz;
    const float length = std::sqrt(a * a + b * b + c * c);
    const float scale = length > 0.0f ? 1.0f / length : 0.0f;
    posed_normals_(i, 0) = a * scale, posed_normals_(i, 1) = b * scale, posed_normals_(i, 2) = c * scale;
  }
  const int32_t n = static_cast<int32_t>(candidate_offsets_.size()) - 1;
  for (int32_t v = 0; v < n; ++v) {
    float* p = positions + 3 * static_cast<size_t>(v);
    int32_t best = -1;
    float best_d2 = kReach * kReach;
    for (int32_t k = candidate_offsets_[v]; k < candidate_offsets_[v + 1]; ++k) {
      const int32_t c = candidates_[k];
      const float dx = p[0] - posed_(c, 0), dy = p[1] - posed_(c, 1), dz = p[2] - posed_(c, 2);
      const float d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < best_d2) best_d2 = d2, best = c;
    }
    if (best < 0) continue;
    const float depth = (p[0] - posed_(best, 0)) * posed_normals_(best, 0) +
                        (p[1] - posed_(best, 1)) * posed_normals_(best, 1) +
                        (p[2] - posed_(best, 2)) * posed_normals_(best, 2);
    if (depth >= distance) continue;
    const float push = distance - depth;
    for (int k = 0; k < 3; ++k) p[k] += push * posed_normals_(best, k);
  }
}

}  // namespace pleat::runtime
