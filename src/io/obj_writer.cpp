#include "io/obj_writer.h"

#include <charconv>
#include <cmath>

#include "core/error.h"
#include "io/atomic_file.h"

namespace pleat {
namespace {

// Appends "<tag> x y z\n" with shortest round-trip floats (locale-independent,
// unlike printf, which writes decimal commas under some locales).
void append_vector(std::string* out, const char* tag, const float* xyz) {
  char text[64];
  out->append(tag);
  for (int k = 0; k < 3; ++k) {
    out->push_back(' ');
    auto result = std::to_chars(text, text + sizeof(text), xyz[k]);
    out->append(text, result.ptr);
  }
  out->push_back('\n');
}

void check_finite(const float* values, size_t vertex_count, const char* what) {
  for (size_t i = 0; i < 3 * vertex_count; ++i)
    if (!std::isfinite(values[i]))
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           std::string(what) + " of vertex " + std::to_string(i / 3) + " is not finite");
}

}  // namespace

void check_triangles(const Triangles& triangles, size_t vertex_count) {
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int32_t v = triangles(f, k);
      if (v < 0 || static_cast<size_t>(v) >= vertex_count)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, "triangle " + std::to_string(f) + " corner " + std::to_string(k) +
                                               ": index " + std::to_string(v) + " outside [0, " +
                                               std::to_string(vertex_count) + ")");
    }
}

void write_obj(const std::string& path, const float* positions, size_t vertex_count,
               const Triangles& triangles, const float* normals) {
  AtomicFile file(path);
  write_obj(file, positions, vertex_count, triangles, normals);
  file.commit();
}

void write_obj(AtomicFile& file, const float* positions, size_t vertex_count, const Triangles& triangles,
               const float* normals) {
  check_finite(positions, vertex_count, "position");
  if (normals) check_finite(normals, vertex_count, "normal");
  check_triangles(triangles, vertex_count);
  std::string text = "# written by pleat\n";
  text.reserve(size_t{40} * vertex_count * (normals ? 2 : 1));
  for (size_t v = 0; v < vertex_count; ++v) append_vector(&text, "v", positions + 3 * v);
  if (normals)
    for (size_t v = 0; v < vertex_count; ++v) append_vector(&text, "vn", normals + 3 * v);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    text.push_back('f');
    for (int k = 0; k < 3; ++k) {
      std::string index = std::to_string(triangles(f, k) + 1);
      text += ' ' + index;
      if (normals) text += "//" + index;
    }
    text.push_back('\n');
  }
  file.write(text);
}

}  // namespace pleat
