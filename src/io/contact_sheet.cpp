#include "io/contact_sheet.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "io/atomic_file.h"

namespace pleat {
namespace {

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  std::vector<float> depth;
  Image(int w, int h)
      : width(w), height(h), rgb(static_cast<size_t>(w) * h * 3, 255), depth(static_cast<size_t>(w) * h) {}
};

// Screen coordinates of a view: right, up and towards the viewer.
Eigen::Vector3f to_view(const float* p, int view) {
  if (view == 0) return {p[0], p[1], p[2]};
  return {-p[2], p[1], p[0]};
}

// One triangle into the cell at (x0, y0) of size w x h; screen position =
// centre + scale * (view coordinates - origin).
void draw_triangle(Image& image, int x0, int y0, int w, int h, const Eigen::Vector3f (&v)[3], float scale,
                   const Eigen::Vector2f& origin, const std::array<uint8_t, 3>& color) {
  Eigen::Vector2f s[3];
  for (int k = 0; k < 3; ++k)
    s[k] = {x0 + 0.5f * w + scale * (v[k].x() - origin.x()), y0 + 0.5f * h - scale * (v[k].y() - origin.y())};
  const float area = (s[1] - s[0]).x() * (s[2] - s[0]).y() - (s[1] - s[0]).y() * (s[2] - s[0]).x();
  if (std::abs(area) < 1e-12f) return;
  const Eigen::Vector3f normal = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
  const float shade = 0.3f + 0.7f * std::abs(normal.z());  // light from the viewer, two-sided
  const int left = std::max(x0, static_cast<int>(std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}))));
  const int right =
      std::min(x0 + w - 1, static_cast<int>(std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}))));
  const int top = std::max(y0, static_cast<int>(std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}))));
  const int bottom =
      std::min(y0 + h - 1, static_cast<int>(std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}))));
  for (int y = top; y <= bottom; ++y)
    for (int x = left; x <= right; ++x) {
      const Eigen::Vector2f p(x + 0.5f, y + 0.5f);
      float b[3];
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2f& a = s[(k + 1) % 3];
        const Eigen::Vector2f& c = s[(k + 2) % 3];
        b[k] = ((c - a).x() * (p - a).y() - (c - a).y() * (p - a).x()) / area;
      }
      if (b[0] < 0 || b[1] < 0 || b[2] < 0) continue;
      const float z = b[0] * v[0].z() + b[1] * v[1].z() + b[2] * v[2].z();
      const size_t i = static_cast<size_t>(y) * image.width + x;
      if (z <= image.depth[i]) continue;
      image.depth[i] = z;
      for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] = static_cast<uint8_t>(shade * color[c]);
    }
}

void check_mesh(const SheetMesh& m, size_t frame) {
  const std::string where = "contact sheet frame " + std::to_string(frame);
  if (!m.positions || m.vertex_count <= 0 || !m.triangles)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, where + ": an empty mesh");
  for (int64_t i = 0; i < 3 * m.vertex_count; ++i)
    if (!std::isfinite(m.positions[i]))
      fail(PLEAT_ERROR_INVALID_ARGUMENT, where + ": vertex " + std::to_string(i / 3) + " is not finite");
  for (Eigen::Index i = 0; i < m.triangles->size(); ++i)
    if (m.triangles->data()[i] < 0 || m.triangles->data()[i] >= m.vertex_count)
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           where + ": triangle index " + std::to_string(m.triangles->data()[i]) + " is out of range");
}

void write_png(const std::string& path, const Image& image) {
  std::vector<uint8_t> bytes;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    fail(PLEAT_ERROR_OUT_OF_MEMORY, "cannot start a PNG for '" + path + "'");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    fail(PLEAT_ERROR_INTERNAL, "libpng failed encoding '" + path + "'");
  }
  png_set_write_fn(
      png, &bytes,
      [](png_structp p, png_bytep data, png_size_t n) {
        auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(p));
        out->insert(out->end(), data, data + n);
      },
      nullptr);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y)
    png_write_row(png, const_cast<png_bytep>(image.rgb.data() + static_cast<size_t>(y) * image.width * 3));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  AtomicFile file(path);
  file.write(bytes.data(), bytes.size());
  file.commit();
}

}  // namespace

void write_contact_sheet(const std::string& path, const std::vector<std::vector<SheetMesh>>& frames,
                         int cell_height) {
  if (frames.empty()) fail(PLEAT_ERROR_INVALID_ARGUMENT, "contact sheet '" + path + "': no frames");
  if (cell_height < 16 || cell_height > 4096)
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         "contact sheet cell height " + std::to_string(cell_height) + " is not in 16..4096");
  for (size_t f = 0; f < frames.size(); ++f)
    for (const SheetMesh& m : frames[f]) check_mesh(m, f);
  const int cell_width = cell_height * 2 / 3, columns = static_cast<int>(frames.size());
  Image image(cell_width * columns, cell_height * 2);
  // One scale for the sheet: the largest frame extent of either view fills
  // 90 % of a cell.
  std::vector<std::array<Eigen::Vector2f, 2>> centre(frames.size());
  float extent = 1e-6f;
  for (size_t f = 0; f < frames.size(); ++f)
    for (int view = 0; view < 2; ++view) {
      Eigen::Vector2f lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
      for (const SheetMesh& m : frames[f])
        for (int64_t v = 0; v < m.vertex_count; ++v) {
          const Eigen::Vector3f p = to_view(m.positions + 3 * v, view);
          lo = lo.cwiseMin(p.head<2>()), hi = hi.cwiseMax(p.head<2>());
        }
      if (frames[f].empty()) continue;
      centre[f][static_cast<size_t>(view)] = 0.5f * (lo + hi);
      extent = std::max({extent, (hi.x() - lo.x()) * cell_height / cell_width, hi.y() - lo.y()});
    }
  const float scale = 0.9f * static_cast<float>(cell_height) / extent;
  std::fill(image.depth.begin(), image.depth.end(), -std::numeric_limits<float>::infinity());
  for (size_t f = 0; f < frames.size(); ++f)
    for (int view = 0; view < 2; ++view)
      for (const SheetMesh& m : frames[f])
        for (Eigen::Index t = 0; t < m.triangles->rows(); ++t) {
          Eigen::Vector3f v[3];
          for (int k = 0; k < 3; ++k) v[k] = to_view(m.positions + 3 * (*m.triangles)(t, k), view);
          draw_triangle(image, static_cast<int>(f) * cell_width, view * cell_height, cell_width, cell_height,
                        v, scale, centre[f][static_cast<size_t>(view)], m.color);
        }
  write_png(path, image);
}

}  // namespace pleat
