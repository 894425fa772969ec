#pragma once
// MakeHuman clothes binding (.mhclo): how a garment's vertices follow the
// base mesh, so one garment fits every body shape (issue 6; the format is
// described in ../shared/data/garments/GARMENTS.md). Each garment vertex is
// either a copy of one base vertex or w0 B[i0] + w1 B[i1] + w2 B[i2] + S d,
// with B the shaped base mesh (all 19158 base.obj vertices, helpers
// included) and S = diag(sx, sy, sz), sx = |B[a].x - B[b].x| / reference
// from the file's x_scale line (likewise y and z). The reference lengths
// are base.obj units; with B in metres S carries the unit change too.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace pleat {

struct ClothesBinding {
  std::string name;
  std::string obj_file;  // relative to the .mhclo
  struct Reference {
    std::array<int32_t, 3> vertex{};
    std::array<double, 3> weight{};
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // base.obj units, scaled by S
  };
  std::vector<Reference> vertices;                         // one per garment OBJ "v" line, in order
  std::array<std::array<int32_t, 2>, 3> scale_vertices{};  // x, y, z: the two base vertices
  std::array<double, 3> scale_reference{};                 // their distance on the unshaped base mesh
  std::vector<int32_t> deleted_base_vertices;              // base vertices hidden under the garment
};

// Throws PLEAT_ERROR_IO (missing file) or PLEAT_ERROR_FORMAT naming the file
// and line (a line that is neither "i" nor "i0 i1 i2 w0 w1 w2 dx dy dz", a
// missing or malformed *_scale line, a non-finite number).
ClothesBinding read_mhclo(const std::string& path);

// Garment vertices on the shaped base mesh `base` (every base.obj vertex, in
// the order of its "v" lines). Throws PLEAT_ERROR_INVALID_ARGUMENT naming the
// garment vertex whose reference is outside `base`.
Points3d fit_clothes(const ClothesBinding& binding, const Points3d& base);

}  // namespace pleat
