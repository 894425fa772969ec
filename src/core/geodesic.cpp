#include "core/geodesic.h"

#include <algorithm>
#include <limits>
#include <queue>

namespace pleat {

Csr geodesic_neighbourhoods(const Points3d& vertices, const Csr& graph, double radius) {
  const int32_t n = graph.vertex_count();
  Csr result;
  result.offsets.assign(static_cast<size_t>(n) + 1, 0);
  // Distances live in one array reset only where a search touched it, so each
  // search costs its neighbourhood's size, not N.
  std::vector<double> dist(static_cast<size_t>(n), std::numeric_limits<double>::infinity());
  std::vector<int32_t> touched;
  using Entry = std::pair<double, int32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (int32_t source = 0; source < n; ++source) {
    dist[source] = 0.0;
    touched.push_back(source);
    queue.push({0.0, source});
    while (!queue.empty()) {
      auto [d, v] = queue.top();
      queue.pop();
      if (d > dist[v]) continue;
      for (int32_t k = graph.offsets[v]; k < graph.offsets[v + 1]; ++k) {
        int32_t w = graph.indices[k];
        double nd = d + (vertices.row(v) - vertices.row(w)).norm();
        if (nd < radius && nd < dist[w]) {
          if (dist[w] == std::numeric_limits<double>::infinity()) touched.push_back(w);
          dist[w] = nd;
          queue.push({nd, w});
        }
      }
    }
    std::sort(touched.begin(), touched.end());
    for (int32_t w : touched) {
      if (w != source) result.indices.push_back(w);
      dist[w] = std::numeric_limits<double>::infinity();
    }
    touched.clear();
    result.offsets[source + 1] = static_cast<int32_t>(result.indices.size());
  }
  return result;
}

}  // namespace pleat
