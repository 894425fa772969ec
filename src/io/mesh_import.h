#pragma once
// Triangle meshes from glTF (io/gltf_scene), and OBJ, FBX and the other
// formats assimp reads (io/scene_file).
#include <string>

#include "core/mesh.h"

namespace pleat {

struct ImportedMesh {
  Points3d vertices;  // in metres where the file declares its unit
  Triangles triangles;
  double unit_scale = 1.0;  // factor applied from the file's own unit metadata
};

// Loads every mesh of the file's scene, with node transforms applied, into one
// triangle soup. Points and lines are dropped; polygons are triangulated.
// Throws PLEAT_ERROR_IO (unreadable) or PLEAT_ERROR_FORMAT (the reader's reason).
ImportedMesh import_mesh(const std::string& path);

}  // namespace pleat
