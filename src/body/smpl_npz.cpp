#include "body/smpl_npz.h"

#include <cmath>

#include "core/error.h"
#include "io/npz.h"

namespace pleat {
namespace {

const char* const kSmplJointNames[24] = {
    "pelvis",     "left_hip",    "right_hip",    "spine1",      "left_knee",     "right_knee",
    "spine2",     "left_ankle",  "right_ankle",  "spine3",      "left_foot",     "right_foot",
    "neck",       "left_collar", "right_collar", "head",        "left_shoulder", "right_shoulder",
    "left_elbow", "right_elbow", "left_wrist",   "right_wrist", "left_hand",     "right_hand"};

const NpyArray& need(const NpzArchive& a, const std::string& name, const std::string& path) {
  auto it = a.find(name);
  if (it == a.end()) fail(PLEAT_ERROR_FORMAT, path + ": missing array '" + name + "'");
  return it->second;
}

// Checks the shape; -1 in `expected` matches any size.
void expect_shape(const NpyArray& a, const std::string& name, const std::vector<int64_t>& expected,
                  const std::string& meaning, const std::string& path) {
  bool ok = a.shape.size() == expected.size();
  for (size_t d = 0; ok && d < expected.size(); ++d) ok = expected[d] < 0 || expected[d] == a.shape[d];
  if (!ok)
    fail(PLEAT_ERROR_FORMAT,
         path + ": array '" + name + "' has shape " + shape_string(a.shape) + ", expected " + meaning);
}

void expect_finite(const NpyArray& a, const std::string& name, int64_t row_size, const std::string& row_word,
                   const std::string& path) {
  for (size_t i = 0; i < a.values.size(); ++i)
    if (!std::isfinite(a.values[i]))
      fail(PLEAT_ERROR_INVALID_ARGUMENT, path + ": array '" + name + "' has a non-finite value at " +
                                             row_word + " " +
                                             std::to_string(static_cast<int64_t>(i) / row_size) +
                                             " (flat index " + std::to_string(i) + ")");
}

// Row-major copy of an array seen as rows x cols.
Eigen::MatrixXd as_matrix(const NpyArray& a, Eigen::Index rows, Eigen::Index cols) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(a.values.data(), rows, cols);
}

int64_t integral(const NpyArray& a, size_t i, const std::string& name, const std::string& path) {
  if (a.integer) return a.integers[i];
  const double x = a.values[i];
  if (!std::isfinite(x) || x != std::floor(x))
    fail(PLEAT_ERROR_FORMAT, path + ": array '" + name + "' holds a non-integer " + std::to_string(x) +
                                 " at flat index " + std::to_string(i));
  return static_cast<int64_t>(x);
}

}  // namespace

SmplModel load_smpl_npz(const std::string& path) {
  const std::vector<std::string> names = {"v_template", "shapedirs",     "posedirs", "J_regressor",
                                          "weights",    "kintree_table", "f"};
  const NpzArchive a = read_npz(path, names);
  for (const auto& n : names) need(a, n, path);
  const NpyArray& vt = a.at("v_template");
  const NpyArray& sd = a.at("shapedirs");
  const NpyArray& pd = a.at("posedirs");
  const NpyArray& jr = a.at("J_regressor");
  const NpyArray& wt = a.at("weights");
  const NpyArray& kt = a.at("kintree_table");
  const NpyArray& f = a.at("f");

  expect_shape(vt, "v_template", {-1, 3}, "(V, 3)", path);
  const int64_t v = vt.shape[0];
  if (v == 0) fail(PLEAT_ERROR_FORMAT, path + ": array 'v_template' has no vertices");
  expect_shape(kt, "kintree_table", {2, -1}, "(2, J)", path);
  const int64_t j = kt.shape[1];
  if (j == 0) fail(PLEAT_ERROR_FORMAT, path + ": array 'kintree_table' has no joints");
  const std::string vs = std::to_string(v), js = std::to_string(j);
  expect_shape(sd, "shapedirs", {v, 3, -1}, "(" + vs + ", 3, B) for V = " + vs, path);
  expect_shape(pd, "posedirs", {v, 3, 9 * (j - 1)},
               "(" + vs + ", 3, " + std::to_string(9 * (j - 1)) + ") for V = " + vs + ", J = " + js, path);
  expect_shape(jr, "J_regressor", {j, v}, "(" + js + ", " + vs + ") = (J, V) (a dense matrix)", path);
  expect_shape(wt, "weights", {v, j}, "(" + vs + ", " + js + ") = (V, J)", path);
  expect_shape(f, "f", {-1, 3}, "(F, 3)", path);

  expect_finite(vt, "v_template", 3, "vertex", path);
  expect_finite(sd, "shapedirs", 3 * sd.shape[2], "vertex", path);
  expect_finite(pd, "posedirs", 3 * pd.shape[2], "vertex", path);
  expect_finite(jr, "J_regressor", v, "joint", path);
  expect_finite(wt, "weights", j, "vertex", path);

  SmplModel m;
  m.source = path;
  m.v_template = Eigen::Map<const Points3d>(vt.values.data(), v, 3);
  m.shapedirs = as_matrix(sd, 3 * v, sd.shape[2]);
  m.posedirs = as_matrix(pd, 3 * v, pd.shape[2]);
  m.j_regressor = as_matrix(jr, j, v);

  // Kinematic tree: one root (joint 0), parents first, no cycles.
  m.parents.resize(static_cast<size_t>(j));
  for (int64_t k = 0; k < j; ++k) {
    const int64_t p = integral(kt, static_cast<size_t>(k), "kintree_table", path);
    const int64_t id = integral(kt, static_cast<size_t>(j + k), "kintree_table", path);
    if (id != k)
      fail(PLEAT_ERROR_INVALID_ARGUMENT, path + ": kintree_table row 1 column " + std::to_string(k) + " is " +
                                             std::to_string(id) + "; expected joint ids 0..J-1 in order");
    const bool root = p == -1 || p == 4294967295LL;
    if (!root && (p < 0 || p >= j))
      fail(PLEAT_ERROR_INVALID_ARGUMENT, path + ": kintree_table: joint " + std::to_string(k) +
                                             " has parent " + std::to_string(p) + ", outside 0.." +
                                             std::to_string(j - 1));
    m.parents[static_cast<size_t>(k)] = root ? -1 : static_cast<int32_t>(p);
  }
  for (int64_t k = 0; k < j; ++k) {
    int64_t at = k;
    for (int64_t steps = 0; at >= 0; ++steps) {
      if (steps > j)
        fail(PLEAT_ERROR_INVALID_ARGUMENT,
             path + ": kintree_table has a cycle through joint " + std::to_string(k));
      at = m.parents[static_cast<size_t>(at)];
    }
  }
  for (int64_t k = 0; k < j; ++k) {
    const int32_t p = m.parents[static_cast<size_t>(k)];
    if (k == 0 && p != -1)
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           path + ": kintree_table: joint 0 must be the root, its parent is " + std::to_string(p));
    if (k > 0 && p == -1)
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           path + ": kintree_table: joint " + std::to_string(k) + " is a second root");
    if (k > 0 && p >= k)
      fail(PLEAT_ERROR_INVALID_ARGUMENT, path + ": kintree_table: joint " + std::to_string(k) + "'s parent " +
                                             std::to_string(p) +
                                             " comes after it (pleat needs parents first)");
  }

  // Weights: non-negative rows summing to 1, kept as given.
  const Eigen::MatrixXd dense = as_matrix(wt, v, j);
  m.weights = skin_weights_from_dense(dense, 0.0);
  validate_skin_weights(m.weights, static_cast<int32_t>(v), path + ": weights");

  m.faces.resize(f.shape[0], 3);
  for (int64_t t = 0; t < f.shape[0]; ++t)
    for (int c = 0; c < 3; ++c) {
      const int64_t x = integral(f, static_cast<size_t>(3 * t + c), "f", path);
      if (x < 0 || x >= v)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, path + ": array 'f' face " + std::to_string(t) +
                                               " refers to vertex " + std::to_string(x) + " of " + vs);
      m.faces(t, c) = static_cast<int32_t>(x);
    }

  for (int64_t k = 0; k < j; ++k)
    m.joint_names.push_back(j == 24 ? kSmplJointNames[k] : "joint_" + std::to_string(k));
  return m;
}

Points3d smpl_shaped_vertices(const SmplModel& m, const Eigen::VectorXd& beta) {
  if (beta.size() > m.shape_count())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, m.source + ": beta has " + std::to_string(beta.size()) +
                                           " entries, the model " + std::to_string(m.shape_count()) +
                                           " shape directions");
  for (Eigen::Index i = 0; i < beta.size(); ++i)
    if (!std::isfinite(beta[i]))
      fail(PLEAT_ERROR_INVALID_ARGUMENT, m.source + ": beta[" + std::to_string(i) + "] is not finite");
  const Eigen::VectorXd offsets = m.shapedirs.leftCols(beta.size()) * beta;
  return m.v_template + Eigen::Map<const Points3d>(offsets.data(), m.vertex_count(), 3);
}

Points3d smpl_joints(const SmplModel& m, const Points3d& shaped) {
  if (shaped.rows() != m.vertex_count())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, m.source + ": " + std::to_string(shaped.rows()) +
                                           " shaped vertices for " + std::to_string(m.vertex_count()));
  return m.j_regressor * shaped;
}

Body smpl_body(const SmplModel& m, const Eigen::VectorXd& beta) {
  Body b;
  b.source = m.source;
  b.rest.vertices = smpl_shaped_vertices(m, beta);
  b.rest.triangles = m.faces;
  const Points3d joints = smpl_joints(m, b.rest.vertices);
  const int32_t n = m.joint_count();
  b.skeleton.names = m.joint_names;
  b.skeleton.parents = m.parents;
  b.skeleton.rest_translation.resize(n, 3);
  b.skeleton.rest_rotation.assign(static_cast<size_t>(n), Eigen::Quaterniond::Identity());
  for (int32_t k = 0; k < n; ++k)
    b.skeleton.rest_translation.row(k) =
        k == 0 ? joints.row(0) : Eigen::RowVector3d(joints.row(k) - joints.row(m.parents[k]));
  b.weights = m.weights;
  b.pose_blend_shapes = m.posedirs;
  for (int32_t i = 0; i < m.shape_count(); ++i)
    b.shape.push_back({"beta_" + std::to_string(i), i < beta.size() ? beta[i] : 0.0, 0.0, -5.0, 5.0,
                       "coefficient of shape direction " + std::to_string(i) + " (standard deviations)"});
  return b;
}

Quaternions smpl_pose_rotations(const Eigen::Ref<const Eigen::MatrixXd>& axis_angle) {
  if (axis_angle.cols() != 3)
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         "smpl pose: " + std::to_string(axis_angle.cols()) + " columns, expected 3 (axis-angle per joint)");
  Quaternions q;
  for (Eigen::Index k = 0; k < axis_angle.rows(); ++k) {
    const Eigen::Vector3d r = axis_angle.row(k).transpose();
    if (!r.allFinite())
      fail(PLEAT_ERROR_INVALID_ARGUMENT, "smpl pose: joint " + std::to_string(k) + " is not finite");
    const double angle = r.norm();
    q.push_back(angle < 1e-300 ? Eigen::Quaterniond::Identity()
                               : Eigen::Quaterniond(Eigen::AngleAxisd(angle, r / angle)));
  }
  return q;
}

Points3d smpl_posed_vertices(const SmplModel& m, const Eigen::VectorXd& beta,
                             const Eigen::Ref<const Eigen::MatrixXd>& axis_angle,
                             const Eigen::Vector3d& translation) {
  if (axis_angle.rows() != m.joint_count())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, m.source + ": pose has " + std::to_string(axis_angle.rows()) +
                                           " joints, the model " + std::to_string(m.joint_count()));
  const Body body = smpl_body(m, beta);
  const Eigen::Vector3d root = body.skeleton.rest_translation.row(0).transpose() + translation;
  return pose_body(body, smpl_pose_rotations(axis_angle), root);
}

}  // namespace pleat
