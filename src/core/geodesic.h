#pragma once
// Rest-pose geodesic neighbourhoods for the self-collision loss (paper Eq. 15):
// pairs closer than a radius along the surface are never pushed apart.
#include "core/mesh.h"

namespace pleat {

// For every vertex, the other vertices whose shortest edge-path distance on
// the rest mesh is below `radius` (Dijkstra over mesh edges, which bounds the
// true geodesic distance from above). Neighbours sorted ascending.
Csr geodesic_neighbourhoods(const Points3d& vertices, const Csr& graph, double radius);

}  // namespace pleat
