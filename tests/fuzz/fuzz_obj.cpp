// OBJ in file order (garments, sequence rest meshes, MakeHuman base.obj).
#include "fuzz_support.h"
#include "io/obj_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] {
    pleat::ObjGroups groups;
    const pleat::TriMesh mesh =
        pleat::read_obj_file_order(pleat_fuzz::input_file(data, size, "in.obj"), &groups);
    pleat_fuzz::require_valid_mesh(mesh.vertices, mesh.triangles);
    pleat_fuzz::require(groups.of_triangle.size() == size_t(mesh.triangles.rows()), "a group per triangle");
    for (int32_t g : groups.of_triangle)
      pleat_fuzz::require(g >= -1 && g < int32_t(groups.names.size()), "group index in range");
  });
}
