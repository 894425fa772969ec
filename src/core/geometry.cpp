#include "core/geometry.h"

#include <Eigen/Geometry>

namespace pleat {

template <typename Scalar>
Points<Scalar> face_normals(const Points<Scalar>& x, const Triangles& t) {
  using Vec = Eigen::Matrix<Scalar, 1, 3>;
  Points<Scalar> n(t.rows(), 3);
  for (Eigen::Index f = 0; f < t.rows(); ++f) {
    Vec a = x.row(t(f, 0)), b = x.row(t(f, 1)), c = x.row(t(f, 2));
    Vec cr = (b - a).cross(c - a);
    Scalar len = cr.norm();
    n.row(f) = len > Scalar(0) ? Vec(cr / len) : Vec::Zero();
  }
  return n;
}

template <typename Scalar>
void vertex_normals(const Scalar* x, Eigen::Index vertex_count, const Triangles& t, Scalar* normals) {
  using Vec = Eigen::Matrix<Scalar, 1, 3>;
  using Rows = Eigen::Map<Eigen::Matrix<Scalar, Eigen::Dynamic, 3, Eigen::RowMajor>>;
  const Eigen::Map<const Eigen::Matrix<Scalar, Eigen::Dynamic, 3, Eigen::RowMajor>> p(x, vertex_count, 3);
  Rows n(normals, vertex_count, 3);
  n.setZero();
  for (Eigen::Index f = 0; f < t.rows(); ++f) {
    Vec a = p.row(t(f, 0)), b = p.row(t(f, 1)), c = p.row(t(f, 2));
    Vec cr = (b - a).cross(c - a);  // length = twice the area: area weighting
    for (int k = 0; k < 3; ++k) n.row(t(f, k)) += cr;
  }
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    Scalar len = n.row(v).norm();
    if (len > Scalar(0)) n.row(v) /= len;
  }
}

template <typename Scalar>
Points<Scalar> vertex_normals(const Points<Scalar>& x, const Triangles& t) {
  Points<Scalar> n(x.rows(), 3);
  vertex_normals(x.data(), x.rows(), t, n.data());
  return n;
}

template Points<float> face_normals(const Points<float>&, const Triangles&);
template Points<double> face_normals(const Points<double>&, const Triangles&);
template Points<float> vertex_normals(const Points<float>&, const Triangles&);
template Points<double> vertex_normals(const Points<double>&, const Triangles&);
template void vertex_normals(const float*, Eigen::Index, const Triangles&, float*);
template void vertex_normals(const double*, Eigen::Index, const Triangles&, double*);

Eigen::VectorXd face_areas(const Points3d& x, const Triangles& t) {
  Eigen::VectorXd area(t.rows());
  for (Eigen::Index f = 0; f < t.rows(); ++f) {
    Eigen::RowVector3d a = x.row(t(f, 0)), b = x.row(t(f, 1)), c = x.row(t(f, 2));
    area[f] = 0.5 * (b - a).cross(c - a).norm();
  }
  return area;
}

Eigen::VectorXd vertex_areas(const Points3d& x, const Triangles& t) {
  Eigen::VectorXd fa = face_areas(x, t);
  Eigen::VectorXd area = Eigen::VectorXd::Zero(x.rows());
  for (Eigen::Index f = 0; f < t.rows(); ++f)
    for (int k = 0; k < 3; ++k) area[t(f, k)] += fa[f] / 3.0;
  return area;
}

}  // namespace pleat
