#include "core/nearest_points.h"

#include <limits>

#include "capi/pleat.h"
#include "core/box_tree.h"
#include "core/error.h"

namespace pleat {

std::vector<int32_t> nearest_points(const Points3d& points, const Points3d& queries) {
  if (points.rows() == 0) fail(PLEAT_ERROR_INVALID_ARGUMENT, "nearest_points: the point set is empty");
  std::vector<Box> boxes(static_cast<size_t>(points.rows()));
  Box all;
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    boxes[i].extend(points.row(i).transpose());
    all.extend(boxes[i]);
  }
  const BoxTree tree(std::move(boxes));
  // A first radius of about the spacing of the points; it quadruples until
  // the best hit lies within it (then nothing outside the box can be nearer).
  const double diagonal = (all.hi - all.lo).norm();
  const double start = std::max(1e-9, 0.01 * diagonal);
  std::vector<int32_t> nearest(static_cast<size_t>(queries.rows()), 0);
  for (Eigen::Index q = 0; q < queries.rows(); ++q) {
    const Eigen::Vector3d p = queries.row(q).transpose();
    if (!p.allFinite())
      fail(PLEAT_ERROR_INVALID_ARGUMENT, "nearest_points: query " + std::to_string(q) + " is not finite");
    double best = std::numeric_limits<double>::infinity();
    int32_t best_index = -1;
    for (double radius = start;; radius *= 4.0) {
      Box query;
      query.extend(p);
      query.inflate(radius);
      tree.query(query, [&](int32_t i) {
        const double d = (points.row(i).transpose() - p).squaredNorm();
        if (d < best || (d == best && i < best_index)) {
          best = d;
          best_index = i;
        }
      });
      if (best_index >= 0 && best <= radius * radius) break;
    }
    nearest[static_cast<size_t>(q)] = best_index;
  }
  return nearest;
}

}  // namespace pleat
