#pragma once
// What the assimp-based importers (garment meshes, rigged characters and
// clips) share: the check of a file before assimp reads it, and the unit the
// scene declares.
#include <string>

struct aiScene;

namespace pleat {

// Throws PLEAT_ERROR_IO unless `path` is a readable file, and
// PLEAT_ERROR_FORMAT for what assimp 5.2 trusts without checking: a binary
// glTF whose header declares more bytes than the file holds (assimp would
// allocate them first), and an FBX nested more than 64 scopes deep (assimp
// recurses once per scope and would overflow the stack).
void check_assimp_input(const std::string& path);

// Metres per file unit: FBX stores centimetres per unit ("UnitScaleFactor");
// other formats carry no unit and are taken as metres (1).
double scene_unit_scale(const aiScene* scene);

}  // namespace pleat
