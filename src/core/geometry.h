#pragma once
// Per-face and per-vertex geometry of a triangle mesh at given positions.
#include "core/mesh.h"

namespace pleat {

// Unit face normals (zero for degenerate faces) and twice-areas are derived
// from the cross product of the two edges leaving the first corner.
template <typename Scalar>
Points<Scalar> face_normals(const Points<Scalar>& x, const Triangles& t);

// Area-weighted unit vertex normals (zero where no face contributes).
template <typename Scalar>
Points<Scalar> vertex_normals(const Points<Scalar>& x, const Triangles& t);
// The same into caller memory (row-major xyz, vertex_count rows each);
// allocates nothing, for per-frame use.
template <typename Scalar>
void vertex_normals(const Scalar* x, Eigen::Index vertex_count, const Triangles& t, Scalar* normals);

Eigen::VectorXd face_areas(const Points3d& x, const Triangles& t);

// One third of the area of the incident faces (barycentric dual area).
Eigen::VectorXd vertex_areas(const Points3d& x, const Triangles& t);

}  // namespace pleat
