#pragma once
// Point caches as USD ASCII (.usda): one Mesh prim whose `points` carry a time
// sample per frame, the form Blender, Houdini and Maya read as a mesh
// sequence cache. Time codes are frame numbers from 0 at timeCodesPerSecond =
// the frame rate; Y up, metres (metersPerUnit 1), triangles as
// faceVertexCounts / faceVertexIndices, no subdivision. Floats are written
// with the shortest text that reads back to the same float, so the file is
// exact and the same bytes for the same frames.
#include <cstddef>
#include <string>

#include "core/mesh.h"

namespace pleat {

void write_usda_cache(const std::string& path, const float* frames, size_t frame_count, size_t vertex_count,
                      size_t stride, double frame_rate, const Triangles& triangles);

}  // namespace pleat
