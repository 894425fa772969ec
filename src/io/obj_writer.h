#pragma once
// Writes one triangle mesh as a Wavefront OBJ through AtomicFile.
#include <cstddef>
#include <string>

#include "core/mesh.h"

namespace pleat {

class AtomicFile;

// positions: vertex_count xyz floats; normals: the same layout or nullptr.
// Coordinates are written with the shortest text that reads back to the same
// float, so an OBJ round trip is bit-exact. Faces are 1-based "f a b c" (or
// "f a//a b//b c//c" with normals). Throws PLEAT_ERROR_INVALID_ARGUMENT for a
// non-finite value or a triangle index out of range (nothing is written), and
// PLEAT_ERROR_IO when the file cannot be written.
void write_obj(const std::string& path, const float* positions, size_t vertex_count,
               const Triangles& triangles, const float* normals = nullptr);

// The same text into an open file, left for the caller to finish or commit
// (an OBJ sequence commits its frames together).
void write_obj(AtomicFile& file, const float* positions, size_t vertex_count, const Triangles& triangles,
               const float* normals = nullptr);

// Checks every index of `triangles` against vertex_count; the message names the
// triangle and corner at fault. Shared with the OBJ sequence writer so that a
// bad triangle fails before the first frame file is written.
void check_triangles(const Triangles& triangles, size_t vertex_count);

}  // namespace pleat
