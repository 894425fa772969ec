#pragma once
// The unit a scene read by assimp declares, for every assimp-based importer.
struct aiScene;

namespace pleat {

// Metres per file unit: FBX stores centimetres per unit ("UnitScaleFactor");
// other formats carry no unit and are taken as metres (1).
double scene_unit_scale(const aiScene* scene);

}  // namespace pleat
