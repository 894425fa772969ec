#pragma once
// Self-collision of a garment (paper section IV): faces crossed by a mesh edge
// that shares no vertex with them.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace pleat {

// Moller-Trumbore test of the segment p-q against triangle abc, end points and
// triangle border included. A segment parallel to the triangle's plane (or a
// degenerate triangle) does not count: coplanar contact is not a crossing.
bool segment_crosses_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c);

enum class CollisionSearch {
  box_tree,     // candidate pairs from a BVH over the faces' boxes
  brute_force,  // every edge against every face: the reference, for tests and bench
};

// 1 per face crossed by at least one non-adjacent edge (several hits count
// once), 0 otherwise. `edges` are the mesh's unique edges. The pre-filter
// keeps the (edge, face) pairs whose boxes, grown by `prefilter` metres,
// overlap; a crossing pair always overlaps, so the result does not depend on
// the radius, which only widens the margin against round-off.
std::vector<uint8_t> self_intersected_faces(const Points3d& x, const Triangles& t,
                                            const std::vector<Edge>& edges, double prefilter,
                                            CollisionSearch search = CollisionSearch::box_tree);

}  // namespace pleat
