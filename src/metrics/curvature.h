#pragma once
// Discrete Gaussian curvature: the angle defect at a vertex over its
// barycentric dual area (one third of the incident triangle area), in 1/m^2.
#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace pleat {

// 1 for a vertex whose every incident edge is shared by exactly two triangles
// (a closed fan), 0 for boundary, non-manifold and isolated vertices. The
// defect 2*pi - sum of angles is Gaussian curvature only at the former; at a
// boundary vertex pi - sum measures how the boundary curve bends instead, so
// the metric leaves boundary vertices out rather than mixing the two. (A
// "bow-tie" vertex joining two closed fans passes this test; such meshes are
// reported as non-manifold at load.)
std::vector<uint8_t> interior_vertex_mask(const Triangles& t, int32_t vertex_count);

// Sum of the corner angles (radians) incident to each vertex.
Eigen::VectorXd angle_sums(const Points3d& x, const Triangles& t);

// K = (2*pi - angle sum) / (incident area / 3) at interior vertices with a
// positive area; 0 elsewhere (*valid, if given, says which vertices got a K).
Eigen::VectorXd gaussian_curvature(const Points3d& x, const Triangles& t,
                                   const std::vector<uint8_t>& interior,
                                   std::vector<uint8_t>* valid = nullptr);

}  // namespace pleat
