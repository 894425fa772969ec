#include "core/weld.h"

#include <cmath>
#include <unordered_map>

namespace pleat {
namespace {

struct CellKey {
  int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
  size_t operator()(const CellKey& k) const {
    return static_cast<size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};

}  // namespace

WeldResult weld_vertices(const Points3d& vertices, double tolerance) {
  const auto n = static_cast<int32_t>(vertices.rows());
  WeldResult result;
  result.remap.resize(static_cast<size_t>(n));
  std::vector<int32_t> kept;
  kept.reserve(static_cast<size_t>(n));
  if (tolerance < 0.0) {
    for (int32_t v = 0; v < n; ++v) result.remap[v] = v;
    result.vertices = vertices;
    return result;
  }
  // Cells of size `tolerance` (at least a tiny positive size so exact
  // duplicates still share a cell): any match lies in the 27 neighbours.
  const double cell = std::max(tolerance, 1e-12);
  const double tol2 = tolerance * tolerance;
  std::unordered_map<CellKey, std::vector<int32_t>, CellHash> grid;
  grid.reserve(static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v) {
    const Eigen::RowVector3d p = vertices.row(v);
    CellKey key{static_cast<int64_t>(std::floor(p.x() / cell)),
                static_cast<int64_t>(std::floor(p.y() / cell)),
                static_cast<int64_t>(std::floor(p.z() / cell))};
    int32_t match = -1;
    for (int64_t dx = -1; dx <= 1 && match < 0; ++dx)
      for (int64_t dy = -1; dy <= 1 && match < 0; ++dy)
        for (int64_t dz = -1; dz <= 1 && match < 0; ++dz) {
          auto it = grid.find({key.x + dx, key.y + dy, key.z + dz});
          if (it == grid.end()) continue;
          for (int32_t k : it->second)
            if ((vertices.row(kept[k]) - p).squaredNorm() <= tol2) {
              match = k;
              break;
            }
        }
    if (match < 0) {
      match = static_cast<int32_t>(kept.size());
      kept.push_back(v);
      grid[key].push_back(match);
    } else {
      ++result.merged_count;
    }
    result.remap[v] = match;
  }
  result.vertices.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (size_t k = 0; k < kept.size(); ++k)
    result.vertices.row(static_cast<Eigen::Index>(k)) = vertices.row(kept[k]);
  return result;
}

}  // namespace pleat
