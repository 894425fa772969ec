// Point caches read from files: PC2, MDD and OBJ sequences. The first byte
// picks the format (bit 0: PC2; else bit 1: an OBJ sequence, whose frames
// 0 and 1 are the rest split at the first NUL; else MDD).
#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include "fuzz_support.h"
#include "io/point_cache.h"

namespace {

// Frames seq_0000.obj and, where the input holds a NUL, seq_0001.obj; the
// pattern that reads them.
std::string obj_sequence(const uint8_t* data, size_t size) {
  const auto* nul = static_cast<const uint8_t*>(std::memchr(data, 0, size));
  const size_t first = nul ? static_cast<size_t>(nul - data) : size;
  const std::string frame0 = pleat_fuzz::input_file(data, first, "seq_0000.obj");
  const std::filesystem::path frame1 = std::filesystem::path(frame0).parent_path() / "seq_0001.obj";
  if (nul)
    pleat_fuzz::input_file(nul + 1, size - first - 1, "seq_0001.obj");
  else
    std::filesystem::remove(frame1);
  return (std::filesystem::path(frame0).parent_path() / "seq_####.obj").string();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const bool pc2 = data[0] & 1, obj = !pc2 && (data[0] & 2);
  return pleat_fuzz::run([&] {
    const auto format = pc2   ? pleat::CacheFormat::pc2
                        : obj ? pleat::CacheFormat::obj_sequence
                              : pleat::CacheFormat::mdd;
    const std::string path = obj ? obj_sequence(data + 1, size - 1)
                                 : pleat_fuzz::input_file(data + 1, size - 1, pc2 ? "in.pc2" : "in.mdd");
    const pleat::CacheHeader header = pleat::read_cache_header(path, format);
    const double floats = double(header.frame_count) * double(header.vertex_count) * 3;
    if (floats > 1e6) return;  // the header alone was read and checked
    std::vector<float> frames(size_t(floats) + 1, -1.0f);
    pleat::read_cache(path, format, frames.data(), 0, frames.size());
    for (size_t i = 0; i + 1 < frames.size(); ++i)
      pleat_fuzz::require(std::isfinite(frames[i]), "finite positions");
  });
}
