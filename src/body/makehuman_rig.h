#pragma once
// MakeHuman rig files: the skeleton (.mhskel) and its skin weights (.mhw or
// MPFB2's JSON). Internal to makehuman.cpp.
#include <string>
#include <vector>

#include "body/skeleton.h"
#include "body/skinning.h"

namespace pleat {

// Reads the bones of a .mhskel into `skeleton` (names and parents,
// parents first, children in file order; rest transforms left at identity)
// and each bone's head vertex group (indices < vertex_count) into
// `joint_vertices`. Throws PLEAT_ERROR_FORMAT naming the file and the bone.
void read_makehuman_rig(const std::string& path, int32_t vertex_count, Skeleton* skeleton,
                        std::vector<std::vector<int32_t>>* joint_vertices);

// Reads {"weights": {bone: [[vertex, weight], ...]}} into per-vertex weights,
// normalised; vertices without any weight go to the root and are listed in
// `unweighted`. Throws PLEAT_ERROR_FORMAT naming the file, bone and entry.
SkinWeights read_makehuman_weights(const std::string& path, const Skeleton& skeleton, int32_t vertex_count,
                                   std::vector<int32_t>* unweighted);

}  // namespace pleat
