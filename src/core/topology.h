#pragma once
// Connectivity of a triangle mesh: unique edges, the edge graph, components,
// boundary loops and non-manifold edges.
#include <vector>

#include "core/mesh.h"

namespace pleat {

// Unique undirected edges of the triangles, sorted.
std::vector<Edge> unique_edges(const Triangles& triangles);

// Symmetric adjacency of the edges over vertex_count vertices (isolated
// vertices get no neighbours).
Csr edge_graph(const std::vector<Edge>& edges, int32_t vertex_count);

// Component label per vertex (0-based, in order of first vertex) and the count.
int32_t connected_components(const Csr& graph, std::vector<int32_t>* labels);

struct EdgeCensus {
  int32_t boundary_edges = 0;      // used by exactly one triangle
  int32_t non_manifold_edges = 0;  // used by three or more triangles
  int32_t boundary_loops = 0;      // cycles formed by boundary edges
};
EdgeCensus census_edges(const Triangles& triangles, int32_t vertex_count);

}  // namespace pleat
