#pragma once
// Checks of caller frame buffers shared by the entry points that take them.
#include <cmath>
#include <string>

#include "capi/firewall.h"
#include "core/mesh.h"

namespace pleat::capi {

inline size_t resolved_stride(size_t stride, size_t vertex_count, const char* name) {
  if (stride == 0) return vertex_count * 3;
  PLEAT_REQUIRE(stride >= vertex_count * 3,
                std::string("'") + name + ".frame_stride' " + std::to_string(stride) +
                    " is below vertex_count * 3 = " + std::to_string(vertex_count * 3));
  return stride;
}

// Validates an input buffer (non-NULL, finite values); returns its stride.
inline size_t checked_input(pleat_const_frames frames, const char* name, size_t vertex_count,
                            size_t frame_count) {
  PLEAT_REQUIRE(frames.data != nullptr || frame_count == 0, std::string("'") + name + ".data' is NULL");
  const size_t stride = resolved_stride(frames.frame_stride, vertex_count, name);
  for (size_t f = 0; f < frame_count; ++f)
    for (size_t i = 0; i < vertex_count * 3; ++i)
      if (!std::isfinite(frames.data[f * stride + i]))
        fail(PLEAT_ERROR_INVALID_ARGUMENT, std::string("'") + name + "' frame " + std::to_string(f) +
                                               " vertex " + std::to_string(i / 3) + " is not finite");
  return stride;
}

// Output buffers may be NULL (not wanted); returns the stride.
inline size_t checked_output(pleat_frames frames, const char* name, size_t vertex_count) {
  return frames.data ? resolved_stride(frames.frame_stride, vertex_count, name) : 0;
}

// Caller index triples as internal triangles; every index must be below
// vertex_count (the message names `name[i]` and its value).
inline Triangles caller_triangles(const uint32_t* indices, size_t triangle_count, size_t vertex_count,
                                  const std::string& name) {
  Triangles t(static_cast<Eigen::Index>(triangle_count), 3);
  for (size_t i = 0; i < triangle_count * 3; ++i) {
    PLEAT_REQUIRE(indices[i] < vertex_count,
                  name + "[" + std::to_string(i) + "] = " + std::to_string(indices[i]) +
                      " is not below vertex_count " + std::to_string(vertex_count));
    t.data()[i] = static_cast<int32_t>(indices[i]);
  }
  return t;
}

}  // namespace pleat::capi
