// .glb garments: tinygltf and pleat's checked walk of the scene (io/gltf_scene,
// io/mesh_import).
#include "fuzz_support.h"
#include "io/mesh_import.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] {
    const pleat::ImportedMesh mesh = pleat::import_mesh(pleat_fuzz::input_file(data, size, "in.glb"));
    pleat_fuzz::require_valid_mesh(mesh.vertices, mesh.triangles);
  });
}
