// BVH motion clips.
#include <cmath>

#include "body/bvh.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] {
    const pleat::BvhClip clip =
        pleat::parse_bvh(std::string(reinterpret_cast<const char*>(data), size), "fuzz.bvh");
    pleat_fuzz::require(std::isfinite(clip.motion.frame_rate) && clip.motion.frame_rate > 0, "frame rate");
  });
}
