#include "io/obj_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/error.h"

namespace pleat {

TriMesh read_obj_file_order(const std::string& path, ObjGroups* groups) {
  std::ifstream in(path);
  if (!in) fail(PLEAT_ERROR_IO, path + ": cannot open the file");
  std::vector<double> xyz;
  std::vector<int32_t> corners;
  std::string line, word;
  int64_t number = 0;
  const auto bad = [&](const std::string& why) {
    fail(PLEAT_ERROR_FORMAT, path + ": line " + std::to_string(number) + ": " + why);
  };
  std::vector<int32_t> face;
  int32_t group = -1;
  if (groups) *groups = {};
  while (std::getline(in, line)) {
    ++number;
    std::istringstream s(line);
    if (!(s >> word)) continue;
    if (word == "v") {
      double p[3];
      for (double& c : p) {
        char* end = nullptr;
        if (!(s >> word)) bad("is not 'v x y z'");
        c = std::strtod(word.c_str(),
                        &end);  // unlike operator>>, reads "nan" and "inf" to refuse them by name
        if (*end != '\0') bad("is not 'v x y z'");
        if (!std::isfinite(c)) bad("a coordinate is not finite");
      }
      xyz.insert(xyz.end(), p, p + 3);
    } else if (word == "f") {
      face.clear();
      const auto vertices = static_cast<int64_t>(xyz.size() / 3);
      while (s >> word) {
        char* end = nullptr;
        const long long index = std::strtoll(word.c_str(), &end, 10);
        if (end == word.c_str() || (*end != '\0' && *end != '/'))
          bad("corner '" + word + "' is not an index");
        const long long resolved = index < 0 ? vertices + index : index - 1;
        if (index == 0 || resolved < 0 || resolved >= vertices)
          bad("corner '" + word + "' is outside the " + std::to_string(vertices) + " vertices read so far");
        face.push_back(static_cast<int32_t>(resolved));
      }
      if (face.size() < 3) bad("a face needs at least three corners");
      for (size_t k = 1; k + 1 < face.size(); ++k) {
        corners.insert(corners.end(), {face[0], face[k], face[k + 1]});
        if (groups) groups->of_triangle.push_back(group);
      }
    } else if (word == "g" && groups) {
      std::string name;
      std::getline(s >> std::ws, name);
      while (!name.empty() && (name.back() == ' ' || name.back() == '\r')) name.pop_back();
      const auto it = std::find(groups->names.begin(), groups->names.end(), name);
      group = static_cast<int32_t>(it - groups->names.begin());
      if (it == groups->names.end()) groups->names.push_back(name);
    }
  }
  TriMesh mesh;
  mesh.vertices = Eigen::Map<const Points3d>(xyz.data(), static_cast<Eigen::Index>(xyz.size() / 3), 3);
  mesh.triangles =
      Eigen::Map<const Triangles>(corners.data(), static_cast<Eigen::Index>(corners.size() / 3), 3);
  return mesh;
}

}  // namespace pleat
