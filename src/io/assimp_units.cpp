#include "io/assimp_units.h"

#include <assimp/scene.h>

namespace pleat {

double scene_unit_scale(const aiScene* scene) {
  if (!scene->mMetaData) return 1.0;
  double factor = 0.0;
  float factor_f = 0.0f;
  if (scene->mMetaData->Get("UnitScaleFactor", factor) && factor > 0.0) return factor / 100.0;
  if (scene->mMetaData->Get("UnitScaleFactor", factor_f) && factor_f > 0.0f) return factor_f / 100.0;
  return 1.0;
}

}  // namespace pleat
