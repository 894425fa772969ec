// MakeHuman skeletons (.mhskel, JSON) for a base mesh of 19,158 vertices.
#include "body/makehuman_rig.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] {
    pleat::Skeleton skeleton;
    std::vector<std::vector<int32_t>> joint_vertices;
    pleat::read_makehuman_rig(pleat_fuzz::input_file(data, size, "in.mhskel"), 19158, &skeleton,
                              &joint_vertices);
    pleat_fuzz::require(skeleton.parents.size() == skeleton.names.size(), "a parent per bone");
    for (size_t j = 0; j < skeleton.parents.size(); ++j)
      pleat_fuzz::require(skeleton.parents[j] < static_cast<int32_t>(j), "parents come first");
  });
}
