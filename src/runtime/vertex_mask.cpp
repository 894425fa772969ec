#include "runtime/vertex_mask.h"

#include <algorithm>

namespace pleat::runtime {
namespace {

// Flags every vertex within `rings` edges of a flagged one.
void dilate(const nn::AttentionGraph& graph, std::vector<uint8_t>& flags, int32_t rings) {
  std::vector<uint8_t> next;
  for (int32_t r = 0; r < rings; ++r) {
    next = flags;
    for (int32_t v = 0; v < graph.node_count(); ++v) {
      if (!flags[static_cast<size_t>(v)]) continue;
      for (int32_t e = graph.offsets[static_cast<size_t>(v)]; e < graph.offsets[static_cast<size_t>(v) + 1];
           ++e)
        next[static_cast<size_t>(graph.sources[static_cast<size_t>(e)])] = 1;
    }
    flags.swap(next);
  }
}

std::vector<int32_t> flagged(const std::vector<uint8_t>& flags) {
  std::vector<int32_t> vertices;
  for (size_t v = 0; v < flags.size(); ++v)
    if (flags[v]) vertices.push_back(static_cast<int32_t>(v));
  return vertices;
}

SubGraph induced(const nn::AttentionGraph& graph, std::vector<int32_t> vertices) {
  std::vector<int32_t> local(static_cast<size_t>(graph.node_count()), -1);
  for (size_t i = 0; i < vertices.size(); ++i)
    local[static_cast<size_t>(vertices[i])] = static_cast<int32_t>(i);
  SubGraph sub;
  sub.graph.offsets.assign(1, 0);
  for (int32_t v : vertices) {
    int32_t degree = 0;
    for (int32_t e = graph.offsets[static_cast<size_t>(v)]; e < graph.offsets[static_cast<size_t>(v) + 1];
         ++e) {
      const int32_t s = local[static_cast<size_t>(graph.sources[static_cast<size_t>(e)])];
      if (s < 0) continue;
      sub.graph.sources.push_back(s);
      ++degree;
    }
    sub.graph.max_degree = std::max(sub.graph.max_degree, degree);
    sub.graph.offsets.push_back(static_cast<int32_t>(sub.graph.sources.size()));
  }
  sub.vertices = std::move(vertices);
  return sub;
}

// Local index in `within` (ascending) of each of `vertices` (a subset).
std::vector<int32_t> positions_in(const std::vector<int32_t>& within, const std::vector<int32_t>& vertices) {
  std::vector<int32_t> at;
  at.reserve(vertices.size());
  for (int32_t v : vertices)
    at.push_back(static_cast<int32_t>(std::lower_bound(within.begin(), within.end(), v) - within.begin()));
  return at;
}

}  // namespace

VertexMask make_vertex_mask(const nn::AttentionGraph& graph, const uint8_t* mask, int32_t blend_layers,
                            int32_t refinement_layers) {
  const size_t n = static_cast<size_t>(graph.node_count());
  std::vector<uint8_t> flags(n);
  for (size_t v = 0; v < n; ++v) flags[v] = mask[v] != 0;
  VertexMask result;
  if (std::all_of(flags.begin(), flags.end(), [](uint8_t f) { return f != 0; })) return result;
  for (size_t v = 0; v < n; ++v)
    (flags[v] ? result.active : result.masked).push_back(static_cast<int32_t>(v));

  dilate(graph, flags, refinement_layers);
  result.refinement = induced(graph, flagged(flags));
  dilate(graph, flags, 1);
  const std::vector<int32_t> posed = flagged(flags);
  dilate(graph, flags, blend_layers);
  result.blend = induced(graph, flagged(flags));
  result.posed_in_blend = positions_in(result.blend.vertices, posed);
  result.active_in_refinement = positions_in(result.refinement.vertices, result.active);
  return result;
}

}  // namespace pleat::runtime
