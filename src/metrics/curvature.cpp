#include "metrics/curvature.h"

#include <Eigen/Geometry>  // cross products
#include <algorithm>
#include <cmath>

#include "core/geometry.h"

namespace pleat {

constexpr double kPi = 3.14159265358979323846;

std::vector<uint8_t> interior_vertex_mask(const Triangles& t, int32_t vertex_count) {
  std::vector<Edge> half;  // one entry per triangle side, as an undirected edge
  half.reserve(3 * static_cast<size_t>(t.rows()));
  for (Eigen::Index f = 0; f < t.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int32_t a = t(f, k), b = t(f, (k + 1) % 3);
      half.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(half.begin(), half.end());
  std::vector<uint8_t> interior(static_cast<size_t>(vertex_count), 0);
  for (const Edge& e : half) interior[e.a] = interior[e.b] = 1;  // used by a face
  for (size_t i = 0; i < half.size();) {
    size_t j = i;
    while (j < half.size() && half[j] == half[i]) ++j;
    if (j - i != 2) interior[half[i].a] = interior[half[i].b] = 0;
    i = j;
  }
  return interior;
}

Eigen::VectorXd angle_sums(const Points3d& x, const Triangles& t) {
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(x.rows());
  for (Eigen::Index f = 0; f < t.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      Eigen::RowVector3d a = x.row(t(f, k));
      Eigen::RowVector3d u = x.row(t(f, (k + 1) % 3)) - a;
      Eigen::RowVector3d v = x.row(t(f, (k + 2) % 3)) - a;
      // atan2 keeps full precision near 0 and pi, where acos of the cosine
      // does not; a zero-length side gives atan2(0, 0) = 0.
      sums[t(f, k)] += std::atan2(u.cross(v).norm(), u.dot(v));
    }
  return sums;
}

Eigen::VectorXd gaussian_curvature(const Points3d& x, const Triangles& t,
                                   const std::vector<uint8_t>& interior, std::vector<uint8_t>* valid) {
  Eigen::VectorXd sums = angle_sums(x, t);
  Eigen::VectorXd area = vertex_areas(x, t);
  Eigen::VectorXd k = Eigen::VectorXd::Zero(x.rows());
  if (valid) valid->assign(static_cast<size_t>(x.rows()), 0);
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    if (!interior[v] || !(area[v] > 0.0)) continue;
    k[v] = (2.0 * kPi - sums[v]) / area[v];
    if (valid) (*valid)[v] = 1;
  }
  return k;
}

}  // namespace pleat
