#pragma once
// What pleat checks in an FBX file (ASCII or binary) before assimp 5.2 reads
// it: the two structures assimp walks by recursion without a bound, each of
// which a small crafted file turns into a stack overflow that kills the host.
//  - Scopes nested more than 64 deep (assimp's parser recurses once per
//    scope; real files nest about ten deep).
//  - A cycle in the parent links between models (`C: "OO", child, parent`
//    where both are models): assimp's converter descends from the root to
//    each model's children and never returns. Found by fuzz_fbx: a model
//    connected to itself, in an 8.7 kB file.
#include <string>

namespace pleat {

// `bytes` is the whole file. Throws PLEAT_ERROR_FORMAT naming `path` and the
// depth or the model at fault; whatever does not parse is left to assimp.
void check_fbx_before_assimp(const std::string& path, const std::string& bytes);

}  // namespace pleat
