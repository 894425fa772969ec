// C entry points for point caches (PC2, MDD, OBJ sequences, glTF, USD).
#include "capi/firewall.h"
#include "capi/frames.h"
#include "capi/handles.h"
#include "io/point_cache.h"

using namespace pleat;
using namespace pleat::capi;

namespace {

pleat_cache_info to_info(const CacheHeader& h) {
  pleat_cache_info info{};
  info.struct_size = sizeof info;
  info.format = static_cast<uint32_t>(h.format);
  info.frame_count = static_cast<uint64_t>(h.frame_count);
  info.vertex_count = static_cast<uint64_t>(h.vertex_count);
  info.frame_rate = h.frame_rate;
  info.start_time = h.start_time;
  return info;
}

}  // namespace

extern "C" {

pleat_status pleat_cache_get_info(const char* path, uint32_t format, pleat_cache_info* out_info) {
  return guarded(__func__, [&] {
    require_not_null(path, "path");
    require_not_null(out_info, "out_info");
    const CacheFormat f = resolve_cache_format(path, static_cast<CacheFormat>(format));
    write_result(to_info(read_cache_header(path, f)), out_info, "out_info");
  });
}

pleat_status pleat_cache_read(const char* path, uint32_t format, pleat_frames out, size_t capacity) {
  return guarded(__func__, [&] {
    require_not_null(path, "path");
    require_not_null(out.data, "out.data");
    read_cache(path, resolve_cache_format(path, static_cast<CacheFormat>(format)), out.data, out.frame_stride,
               capacity);
  });
}

pleat_status pleat_cache_write(const char* path, uint32_t format, const pleat_garment* garment,
                               pleat_const_frames positions, size_t frame_count, size_t vertex_count,
                               double frame_rate) {
  return guarded(__func__, [&] {
    require_not_null(path, "path");
    const CacheFormat f = resolve_cache_format(path, static_cast<CacheFormat>(format));
    const Triangles* triangles = nullptr;
    if (cache_holds_faces(f)) {
      PLEAT_REQUIRE(garment != nullptr, "argument 'garment' is NULL; this format takes the faces from it");
      PLEAT_REQUIRE(static_cast<size_t>(garment->garment->rest.vertex_count()) == vertex_count,
                    "vertex_count " + std::to_string(vertex_count) + " differs from the garment's " +
                        std::to_string(garment->garment->rest.vertex_count()));
      triangles = &garment->garment->rest.triangles;
    }
    const size_t stride = checked_input(positions, "positions", vertex_count, frame_count);
    write_cache(path, f, positions.data, frame_count, vertex_count, stride, frame_rate, triangles);
  });
}

}  // extern "C"
