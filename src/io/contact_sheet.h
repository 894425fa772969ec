#pragma once
// Preview images without a display: a small software rasteriser (z-buffer,
// flat shading, orthographic) and a PNG writer (libpng). A contact sheet
// shows a few frames side by side, a front view above a side view, each
// frame centred on itself at one scale for the whole sheet (so sizes
// compare across frames). Used by `pleat preview`, the datagen report and
// the trainer's evaluation report.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace pleat {

struct SheetMesh {
  const float* positions = nullptr;  // vertex_count x 3, metres, Y up
  int64_t vertex_count = 0;
  const Triangles* triangles = nullptr;
  std::array<uint8_t, 3> color{200, 200, 200};
};

// frames[f] holds the meshes of frame f (drawn in order, depth-tested).
// Front view: x right, y up, seen from +z; side view: -z right (the
// character's right side), y up. cell_height in pixels, width 2/3 of it.
// Throws PLEAT_ERROR_INVALID_ARGUMENT for no frames, an empty or non-finite
// mesh or an index out of range (named), PLEAT_ERROR_IO when the file cannot
// be written (atomically).
void write_contact_sheet(const std::string& path, const std::vector<std::vector<SheetMesh>>& frames,
                         int cell_height = 360);

}  // namespace pleat
