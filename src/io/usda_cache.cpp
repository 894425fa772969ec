#include "io/usda_cache.h"

#include <charconv>

#include "io/atomic_file.h"

namespace pleat {
namespace {

template <typename T>
void append_number(std::string* out, T value) {
  char text[64];
  auto result = std::to_chars(text, text + sizeof(text), value);
  out->append(text, result.ptr);
}

// "[(x, y, z), ...]" of one frame.
void append_points(std::string* out, const float* xyz, size_t vertex_count) {
  out->push_back('[');
  for (size_t i = 0; i < vertex_count; ++i) {
    out->append(i ? ", (" : "(");
    for (int k = 0; k < 3; ++k) {
      if (k) out->append(", ");
      append_number(out, xyz[3 * i + static_cast<size_t>(k)]);
    }
    out->push_back(')');
  }
  out->push_back(']');
}

}  // namespace

void write_usda_cache(const std::string& path, const float* frames, size_t frame_count, size_t vertex_count,
                      size_t stride, double frame_rate, const Triangles& triangles) {
  AtomicFile file(path);
  std::string text = "#usda 1.0\n(\n    defaultPrim = \"garment\"\n    startTimeCode = 0\n    endTimeCode = ";
  append_number(&text, frame_count - 1);
  text += "\n    timeCodesPerSecond = ";
  append_number(&text, frame_rate);
  text += "\n    framesPerSecond = ";
  append_number(&text, frame_rate);
  text += "\n    metersPerUnit = 1\n    upAxis = \"Y\"\n)\n\n";
  text += "def Xform \"garment\"\n{\n    def Mesh \"mesh\"\n    {\n";
  text += "        uniform token subdivisionScheme = \"none\"\n";
  text += "        int[] faceVertexCounts = [";
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) text += t ? ", 3" : "3";
  text += "]\n        int[] faceVertexIndices = [";
  for (Eigen::Index i = 0; i < triangles.size(); ++i) {
    if (i) text += ", ";
    append_number(&text, triangles.data()[i]);
  }
  text += "]\n        point3f[] points = ";
  append_points(&text, frames, vertex_count);
  text += "\n        point3f[] points.timeSamples = {\n";
  file.write(text);
  for (size_t f = 0; f < frame_count; ++f) {
    text = "            ";
    append_number(&text, f);
    text += ": ";
    append_points(&text, frames + f * stride, vertex_count);
    text += ",\n";
    file.write(text);
  }
  file.write("        }\n    }\n}\n");
  file.commit();
}

}  // namespace pleat
