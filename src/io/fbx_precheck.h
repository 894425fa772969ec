#pragma once
// What pleat checks in an FBX file (ASCII or binary) before assimp 5.2 reads
// it: what assimp trusts without a bound, each of which a small crafted file
// turns into a crash of the host (found by fuzz_fbx, docs/reliability.md).
//  - Scopes nested more than 64 deep (assimp's parser recurses once per
//    scope; real files nest about ten deep).
//  - A cycle in the parent links between models (`C: "OO", child, parent`
//    where both are models): assimp's converter descends from the root to
//    each model's children and never returns (a model connected to itself,
//    8.7 kB, overflowed the stack).
//  - Binary records that reach outside their parent, or whose properties
//    reach outside the record: assimp adds the declared lengths to pointers
//    before comparing them, and its tokenizer aborts on an assertion.
#include <string>

namespace pleat {

// `bytes` is the whole file. Throws PLEAT_ERROR_FORMAT naming `path` and the
// depth, model or byte offset at fault; ASCII that does not tokenise as FBX
// is left to assimp to refuse.
void check_fbx_before_assimp(const std::string& path, const std::string& bytes);

}  // namespace pleat
