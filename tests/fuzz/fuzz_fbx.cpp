// .fbx garments through pleat's checks of the file (io/fbx_precheck), then
// assimp (io/mesh_import).
#include "fuzz_bounded_new.h"
#include "fuzz_support.h"
#include "io/mesh_import.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] {
    const pleat::ImportedMesh mesh = pleat::import_mesh(pleat_fuzz::input_file(data, size, "in.fbx"));
    pleat_fuzz::require_valid_mesh(mesh.vertices, mesh.triangles);
  });
}
