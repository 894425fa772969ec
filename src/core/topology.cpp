#include "core/topology.h"

#include <algorithm>
#include <map>
#include <numeric>

namespace pleat {

std::vector<Edge> unique_edges(const Triangles& triangles) {
  std::vector<Edge> edges;
  edges.reserve(static_cast<size_t>(triangles.rows()) * 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      int32_t a = triangles(f, c), b = triangles(f, (c + 1) % 3);
      if (a == b) continue;
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

Csr edge_graph(const std::vector<Edge>& edges, int32_t vertex_count) {
  Csr g;
  g.offsets.assign(static_cast<size_t>(vertex_count) + 1, 0);
  for (const Edge& e : edges) {
    ++g.offsets[e.a + 1];
    ++g.offsets[e.b + 1];
  }
  std::partial_sum(g.offsets.begin(), g.offsets.end(), g.offsets.begin());
  g.indices.resize(static_cast<size_t>(g.offsets.back()));
  std::vector<int32_t> cursor(g.offsets.begin(), g.offsets.end() - 1);
  for (const Edge& e : edges) {
    g.indices[cursor[e.a]++] = e.b;
    g.indices[cursor[e.b]++] = e.a;
  }
  for (int32_t v = 0; v < vertex_count; ++v)
    std::sort(g.indices.begin() + g.offsets[v], g.indices.begin() + g.offsets[v + 1]);
  return g;
}

int32_t connected_components(const Csr& graph, std::vector<int32_t>* labels) {
  const int32_t n = graph.vertex_count();
  labels->assign(static_cast<size_t>(n), -1);
  std::vector<int32_t> stack;
  int32_t count = 0;
  for (int32_t seed = 0; seed < n; ++seed) {
    if ((*labels)[seed] >= 0) continue;
    (*labels)[seed] = count;
    stack.push_back(seed);
    while (!stack.empty()) {
      int32_t v = stack.back();
      stack.pop_back();
      for (int32_t k = graph.offsets[v]; k < graph.offsets[v + 1]; ++k) {
        int32_t w = graph.indices[k];
        if ((*labels)[w] < 0) {
          (*labels)[w] = count;
          stack.push_back(w);
        }
      }
    }
    ++count;
  }
  return count;
}

EdgeCensus census_edges(const Triangles& triangles, int32_t vertex_count) {
  std::map<Edge, int32_t> use;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      int32_t a = triangles(f, c), b = triangles(f, (c + 1) % 3);
      if (a != b) ++use[{std::min(a, b), std::max(a, b)}];
    }
  }
  EdgeCensus census;
  std::vector<Edge> boundary;
  for (const auto& [edge, count] : use) {
    if (count == 1) boundary.push_back(edge);
    if (count >= 3) ++census.non_manifold_edges;
  }
  census.boundary_edges = static_cast<int32_t>(boundary.size());
  // Boundary loops = independent cycles of the boundary-edge graph: for each
  // component of that graph, edges - vertices + 1 (1 for a simple loop).
  Csr g = edge_graph(boundary, vertex_count);
  std::vector<int32_t> labels;
  int32_t comps = connected_components(g, &labels);
  std::vector<int32_t> verts(static_cast<size_t>(comps), 0), edges(static_cast<size_t>(comps), 0);
  for (int32_t v = 0; v < vertex_count; ++v)
    if (g.degree(v) > 0) ++verts[labels[v]];
  for (const Edge& e : boundary) ++edges[labels[e.a]];
  for (int32_t c = 0; c < comps; ++c)
    if (verts[c] > 0) census.boundary_loops += std::max(0, edges[c] - verts[c] + 1);
  return census;
}

}  // namespace pleat
