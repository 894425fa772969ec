#pragma once
// glTF 2.0 scenes (.gltf, .glb) for the importers that walk an aiScene
// (io/mesh_import, body/rig_import), parsed by tinygltf and checked by pleat
// instead of read by assimp: assimp 5.2.5's glTF importer trusts indices,
// counts and matrix lengths from the file (a heap overflow and a null
// dereference found by fuzz_gltf, fuzz_glb and fuzz_rig, and many more
// reported upstream; docs/reliability.md).
//
// What is read, as assimp's own importer maps it:
//  - the default scene's node tree (matrix or translation/rotation/scale);
//    each root hangs under one identity node named "(glTF scene)";
//  - each primitive of a node's mesh as one aiMesh: triangles, strips and
//    fans as triangles (points and lines skipped), positions only;
//  - a node's skin: one bone per joint, named after its node, with the
//    inverse bind matrix as its offset and the JOINTS_n / WEIGHTS_n pairs as
//    its weights;
//  - each animation's rotation and translation channels, one tick per second
//    (a cubic spline's values without its tangents; scale is not read).
// Images are not decoded. Nodes named twice (or not at all) get unique names
// ("<name>#<index>", "node<index>"), since the importers find bones and
// channels by name.
#include <memory>
#include <string>

struct aiScene;

namespace pleat {

// Throws PLEAT_ERROR_IO (unreadable) or PLEAT_ERROR_FORMAT naming the file
// and the field at fault: JSON tinygltf refuses, an index out of range, an
// accessor reaching past its buffer, a node reached twice (the node graph is
// not a forest) or deeper than 1,000 levels.
std::unique_ptr<aiScene> read_gltf_scene(const std::string& path);

}  // namespace pleat
