#include "metrics/self_collision.h"

#include <Eigen/Geometry>  // cross products
#include <cmath>

#include "core/box_tree.h"

namespace pleat {
namespace {

// Relative threshold on the Moller-Trumbore determinant (a triple product, so
// scaled by the three lengths): below it the segment is taken as parallel.
constexpr double kParallelTolerance = 1e-12;

bool shares_vertex(const Triangles& t, Eigen::Index f, const Edge& e) {
  for (int k = 0; k < 3; ++k)
    if (t(f, k) == e.a || t(f, k) == e.b) return true;
  return false;
}

Eigen::Map<const Eigen::Vector3d> point(const Points3d& x, int32_t v) {
  return Eigen::Map<const Eigen::Vector3d>(x.data() + 3 * static_cast<Eigen::Index>(v));
}

// Most candidate pairs lie wholly on one side of the face's plane; rejecting
// them on two dot products first roughly halves the cost of the search.
struct FacePlane {
  Eigen::Vector3d normal;  // unnormalised
  double offset;
};

FacePlane face_plane(const Points3d& x, const Triangles& t, Eigen::Index f) {
  Eigen::Vector3d a = point(x, t(f, 0));
  Eigen::Vector3d n = (point(x, t(f, 1)) - a).cross(point(x, t(f, 2)) - a);
  return {n, n.dot(a)};
}

bool edge_crosses_face(const Points3d& x, const Triangles& t, const FacePlane& plane, Eigen::Index f,
                       const Edge& e) {
  double side_a = plane.normal.dot(point(x, e.a)) - plane.offset;
  double side_b = plane.normal.dot(point(x, e.b)) - plane.offset;
  if ((side_a > 0.0 && side_b > 0.0) || (side_a < 0.0 && side_b < 0.0)) return false;
  return segment_crosses_triangle(point(x, e.a), point(x, e.b), point(x, t(f, 0)), point(x, t(f, 1)),
                                  point(x, t(f, 2)));
}

}  // namespace

bool segment_crosses_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  Eigen::Vector3d d = q - p, e1 = b - a, e2 = c - a;
  Eigen::Vector3d h = d.cross(e2);
  double det = e1.dot(h);
  if (!(std::abs(det) > kParallelTolerance * d.norm() * e1.norm() * e2.norm())) return false;
  double inv = 1.0 / det;
  Eigen::Vector3d s = p - a;
  double u = inv * s.dot(h);
  if (u < 0.0 || u > 1.0) return false;
  Eigen::Vector3d r = s.cross(e1);
  double v = inv * d.dot(r);
  if (v < 0.0 || u + v > 1.0) return false;
  double along = inv * e2.dot(r);  // parameter on the segment
  return along >= 0.0 && along <= 1.0;
}

std::vector<uint8_t> self_intersected_faces(const Points3d& x, const Triangles& t,
                                            const std::vector<Edge>& edges, double prefilter,
                                            CollisionSearch search) {
  std::vector<uint8_t> hit(static_cast<size_t>(t.rows()), 0);
  std::vector<FacePlane> planes(static_cast<size_t>(t.rows()));
  for (Eigen::Index f = 0; f < t.rows(); ++f) planes[f] = face_plane(x, t, f);
  auto test = [&](Eigen::Index f, const Edge& e) {
    if (!hit[f] && !shares_vertex(t, f, e) && edge_crosses_face(x, t, planes[f], f, e)) hit[f] = 1;
  };
  if (search == CollisionSearch::brute_force) {
    for (const Edge& e : edges)
      for (Eigen::Index f = 0; f < t.rows(); ++f) test(f, e);
    return hit;
  }
  std::vector<Box> face_boxes(static_cast<size_t>(t.rows()));
  for (Eigen::Index f = 0; f < t.rows(); ++f) {
    for (int k = 0; k < 3; ++k) face_boxes[f].extend(point(x, t(f, k)));
    face_boxes[f].inflate(prefilter);
  }
  BoxTree tree(std::move(face_boxes));
  for (const Edge& e : edges) {
    Box box;
    box.extend(point(x, e.a));
    box.extend(point(x, e.b));
    tree.query(box, [&](int32_t f) { test(f, e); });
  }
  return hit;
}

}  // namespace pleat
