// MakeHuman skin weights (.mhw, JSON) on a three-bone skeleton and 64 vertices.
#include <cmath>

#include "body/makehuman_rig.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const pleat::Skeleton skeleton = [] {
    pleat::Skeleton s;
    s.names = {"Hips", "Spine", "Head"};
    s.parents = {-1, 0, 1};
    return s;
  }();
  return pleat_fuzz::run([&] {
    std::vector<int32_t> unweighted;
    const pleat::SkinWeights w = pleat::read_makehuman_weights(pleat_fuzz::input_file(data, size, "in.mhw"),
                                                               skeleton, 64, &unweighted);
    for (int32_t v : unweighted) pleat_fuzz::require(v >= 0 && v < 64, "unweighted vertex in range");
    pleat_fuzz::require(w.vertex_count() == 64, "a weight list per vertex");
    for (size_t i = 0; i < w.joints.size(); ++i)
      pleat_fuzz::require(w.joints[i] >= 0 && w.joints[i] < 3 && std::isfinite(w.weights[i]),
                          "weights valid");
  });
}
