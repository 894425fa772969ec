#include "body/mhclo.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>

#include "capi/pleat.h"
#include "core/error.h"

namespace pleat {
namespace {

constexpr int32_t kMaxDeletedRange = 1 << 20;

[[noreturn]] void bad(const std::string& path, int64_t line, const std::string& what) {
  fail(PLEAT_ERROR_FORMAT, path + ":" + std::to_string(line) + ": " + what);
}

}  // namespace

ClothesBinding read_mhclo(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(PLEAT_ERROR_IO, path + ": cannot open the file");
  ClothesBinding b;
  std::array<bool, 3> has_scale{};
  enum class Section { header, verts, deleted } section = Section::header;
  std::string line;
  int64_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (section == Section::header || !std::isdigit(static_cast<unsigned char>(key[0]))) {
      if (key == "verts") {
        section = Section::verts;
      } else if (key == "delete_verts") {
        section = Section::deleted;
      } else if (key == "name") {
        s >> b.name;
      } else if (key == "obj_file") {
        s >> b.obj_file;
      } else if (key == "x_scale" || key == "y_scale" || key == "z_scale") {
        const int axis = key[0] - 'x';
        auto& v = b.scale_vertices[static_cast<size_t>(axis)];
        double& d = b.scale_reference[static_cast<size_t>(axis)];
        if (!(s >> v[0] >> v[1] >> d) || !(d > 0) || !std::isfinite(d))
          bad(path, number, key + " needs two vertex indices and a positive reference length");
        has_scale[static_cast<size_t>(axis)] = true;
      } else if (section != Section::header) {
        section = Section::header;  // another header-like key ends a section
      }
      continue;
    }
    if (section == Section::verts) {
      std::vector<double> values;
      std::istringstream all(line);
      for (double x; all >> x;) values.push_back(x);
      for (double v : values)
        if (!std::isfinite(v)) bad(path, number, "a number is not finite");
      const auto vertex = [&](double v) {
        if (!(v >= 0.0 && v <= double(INT32_MAX) && v == std::floor(v)))
          bad(path, number, "vertex index " + std::to_string(v) + " is not a vertex index");
        return static_cast<int32_t>(v);
      };
      ClothesBinding::Reference r;
      if (values.size() == 1) {
        r.vertex = {vertex(values[0]), vertex(values[0]), vertex(values[0])};
        r.weight = {1.0, 0.0, 0.0};
      } else if (values.size() == 9) {
        for (int k = 0; k < 3; ++k) {
          r.vertex[static_cast<size_t>(k)] = vertex(values[static_cast<size_t>(k)]);
          r.weight[static_cast<size_t>(k)] = values[static_cast<size_t>(3 + k)];
          r.offset[k] = values[static_cast<size_t>(6 + k)];
        }
      } else {
        bad(path, number,
            "expected 'i' or 'i0 i1 i2 w0 w1 w2 dx dy dz', got " + std::to_string(values.size()) +
                " numbers");
      }
      b.vertices.push_back(r);
    } else {  // delete_verts: numbers and "a - b" ranges
      std::istringstream all(line);
      std::vector<std::string> tokens;
      for (std::string t; all >> t;) tokens.push_back(t);
      const auto vertex = [&](const std::string& token) {
        int32_t v = -1;
        const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), v);
        if (error != std::errc() || end != token.data() + token.size() || v < 0)
          bad(path, number, "'" + token + "' is not a vertex index");
        return v;
      };
      for (size_t i = 0; i < tokens.size(); ++i) {
        if (tokens[i] == "-") bad(path, number, "a range without a start");
        const int32_t first = vertex(tokens[i]);
        if (i + 2 < tokens.size() && tokens[i + 1] == "-") {
          const int32_t last = vertex(tokens[i + 2]);
          // MakeHuman's base mesh has 19,158 vertices (with helpers); a longer
          // range is a damaged file, not a reason to allocate gigabytes.
          if (last < first || last - first > kMaxDeletedRange)
            bad(path, number,
                "range " + tokens[i] + " - " + tokens[i + 2] + " is empty or longer than any base mesh");
          for (int32_t v = first; v <= last; ++v) b.deleted_base_vertices.push_back(v);
          i += 2;
        } else {
          b.deleted_base_vertices.push_back(first);
        }
      }
    }
  }
  for (int axis = 0; axis < 3; ++axis)
    if (!has_scale[static_cast<size_t>(axis)])
      fail(PLEAT_ERROR_FORMAT, path + ": no " + std::string(1, char('x' + axis)) + "_scale line");
  if (b.vertices.empty()) fail(PLEAT_ERROR_FORMAT, path + ": no vertex references after 'verts'");
  return b;
}

Points3d fit_clothes(const ClothesBinding& b, const Points3d& base) {
  const auto check = [&](int32_t v, const std::string& what) {
    if (v < 0 || v >= base.rows())
      fail(PLEAT_ERROR_INVALID_ARGUMENT, "clothes '" + b.name + "': " + what + " refers to base vertex " +
                                             std::to_string(v) + ", the base mesh has " +
                                             std::to_string(base.rows()));
  };
  Eigen::Vector3d scale;
  for (int axis = 0; axis < 3; ++axis) {
    const auto& v = b.scale_vertices[static_cast<size_t>(axis)];
    check(v[0], std::string(1, char('x' + axis)) + "_scale");
    check(v[1], std::string(1, char('x' + axis)) + "_scale");
    scale[axis] =
        std::abs(base(v[0], axis) - base(v[1], axis)) / b.scale_reference[static_cast<size_t>(axis)];
  }
  Points3d out(static_cast<Eigen::Index>(b.vertices.size()), 3);
  for (size_t i = 0; i < b.vertices.size(); ++i) {
    const ClothesBinding::Reference& r = b.vertices[i];
    Eigen::Vector3d x = scale.cwiseProduct(r.offset);
    for (size_t k = 0; k < 3; ++k) {
      check(r.vertex[k], "garment vertex " + std::to_string(i));
      x += r.weight[k] * base.row(r.vertex[k]).transpose();
    }
    out.row(static_cast<Eigen::Index>(i)) = x.transpose();
  }
  return out;
}

}  // namespace pleat
