#pragma once
// Wavefront OBJ read in the file's own order: vertex i is the i-th "v" line
// and faces index those lines directly. Sequence folders (garment.pc2 follows
// garment.obj's "v" lines) and .mhclo garments (one binding per "v" line) need
// exactly that order, which a general importer (assimp splits vertices per
// face corner) does not keep.
#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace pleat {

// "v x y z" lines and "f" lines (v, v/t, v/t/n, v//n corners; negative
// indices count back from the latest "v"); polygons are fan-triangulated;
// every other line is ignored. Throws PLEAT_ERROR_IO for a missing file and
// PLEAT_ERROR_FORMAT naming the file and line for a malformed "v" or "f"
// line, a corner outside the vertices read so far, a face of fewer than
// three corners, or a non-finite coordinate.
// With `groups`, also the "g" lines (MakeHuman's base.obj names its body,
// helper and joint regions so): each line's name (the rest of the line) in
// order of first appearance, and per output triangle the index of the group
// it came under, -1 before the first "g".
struct ObjGroups {
  std::vector<std::string> names;
  std::vector<int32_t> of_triangle;
};
TriMesh read_obj_file_order(const std::string& path, ObjGroups* groups = nullptr);

}  // namespace pleat
