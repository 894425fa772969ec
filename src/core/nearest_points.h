#pragma once
// Nearest point of a fixed set for each of many queries: the garment vertex
// -> body vertex lookups of binding (skinning prior), the LBS baseline and
// the body-penetration metric.
#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace pleat {

// For every row of `queries`, the index of the nearest row of `points`
// (Euclidean; ties go to the lower index). `points` must not be empty.
// O((n + q) log n) through a BoxTree with a growing search radius.
std::vector<int32_t> nearest_points(const Points3d& points, const Points3d& queries);

}  // namespace pleat
