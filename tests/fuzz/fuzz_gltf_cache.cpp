// glTF morph-target point caches (io/gltf_cache.h): JSON or binary, told
// apart by the "glTF" magic, so one file name serves both.
#include <cmath>
#include <vector>

#include "fuzz_support.h"
#include "io/point_cache.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] {
    const std::string path = pleat_fuzz::input_file(data, size, "in.gltf");
    const pleat::CacheHeader header = pleat::read_cache_header(path, pleat::CacheFormat::gltf);
    pleat_fuzz::require(header.frame_count > 0 && header.vertex_count > 0 &&
                            std::isfinite(header.frame_rate) && header.frame_rate > 0.0,
                        "a glTF cache has frames, vertices and a positive rate");
    const double floats = double(header.frame_count) * double(header.vertex_count) * 3;
    if (floats > 1e6) return;
    std::vector<float> frames(static_cast<size_t>(floats));
    pleat::read_cache(path, pleat::CacheFormat::gltf, frames.data(), 0, frames.size());
    for (float v : frames) pleat_fuzz::require(std::isfinite(v), "frames are finite");
  });
}
