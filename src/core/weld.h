#pragma once
// Welding of coincident vertices, so UV seams and split normals do not cut
// the garment's graph into panels.
#include <vector>

#include "core/mesh.h"

namespace pleat {

struct WeldResult {
  Points3d vertices;           // the kept vertices, in order of first use
  std::vector<int32_t> remap;  // input vertex -> kept vertex
  int32_t merged_count = 0;    // input vertices merged into an earlier one
};

// Merges each vertex into the first earlier vertex within `tolerance`
// (Euclidean). A negative tolerance disables welding.
WeldResult weld_vertices(const Points3d& vertices, double tolerance);

}  // namespace pleat
