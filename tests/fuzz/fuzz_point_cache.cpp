// PC2 and MDD point caches; the first byte picks the format.
#include <vector>

#include "fuzz_support.h"
#include "io/point_cache.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const bool pc2 = data[0] & 1;
  return pleat_fuzz::run([&] {
    const std::string path = pleat_fuzz::input_file(data + 1, size - 1, pc2 ? "in.pc2" : "in.mdd");
    const auto format = pc2 ? pleat::CacheFormat::pc2 : pleat::CacheFormat::mdd;
    const pleat::CacheHeader header = pleat::read_cache_header(path, format);
    const double floats = double(header.frame_count) * double(header.vertex_count) * 3;
    if (floats > 1e6) return;  // the header alone was read and checked
    std::vector<float> frames(size_t(floats) + 1, -1.0f);
    pleat::read_cache(path, format, frames.data(), 0, frames.size());
  });
}
