#include "body/skinning.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"

namespace pleat {

namespace {

std::string vertex_name(const std::string& source, int32_t v) {
  return source + ": vertex " + std::to_string(v);
}

void check_matrices(const SkinMatrices& matrices, int32_t joint_count) {
  if (static_cast<int64_t>(matrices.size()) < joint_count)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "skinning: " + std::to_string(matrices.size()) +
                                           " skinning matrices for weights over " +
                                           std::to_string(joint_count) + " joints");
}

// Blends the matrices of one vertex's influences and applies them.
template <typename Scalar>
inline void skin_vertex(const Scalar* in, const SkinMatrix& m, Scalar* out) {
  const double x = static_cast<double>(in[0]), y = static_cast<double>(in[1]), z = static_cast<double>(in[2]);
  for (int r = 0; r < 3; ++r) out[r] = static_cast<Scalar>(m(r, 0) * x + m(r, 1) * y + m(r, 2) * z + m(r, 3));
}

template <typename Scalar>
void lbs_sparse_raw(const Scalar* rest, int32_t vertex_count, const SkinWeights& w,
                    const SkinMatrices& matrices, Scalar* out) {
  for (int32_t v = 0; v < vertex_count; ++v) {
    SkinMatrix blend = SkinMatrix::Zero();
    for (int32_t k = w.offsets[v]; k < w.offsets[v + 1]; ++k)
      blend.noalias() += w.weights[k] * matrices[w.joints[k]];
    skin_vertex(rest + 3 * static_cast<size_t>(v), blend, out + 3 * static_cast<size_t>(v));
  }
}

}  // namespace

int32_t SkinWeights::max_influences() const {
  int32_t m = 0;
  for (int32_t v = 0; v < vertex_count(); ++v) m = std::max(m, influences(v));
  return m;
}

void validate_skin_weights(const SkinWeights& w, int32_t expected_vertices, const std::string& source) {
  if (w.joint_count <= 0) fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": skin weights over no joints");
  if (w.offsets.empty() || w.offsets.front() != 0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": skin weight offsets must start with 0");
  if (w.joints.size() != w.weights.size() || static_cast<size_t>(w.offsets.back()) != w.joints.size())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": skin weight arrays disagree in size (" +
                                           std::to_string(w.joints.size()) + " joints, " +
                                           std::to_string(w.weights.size()) + " weights, last offset " +
                                           std::to_string(w.offsets.back()) + ")");
  if (expected_vertices >= 0 && w.vertex_count() != expected_vertices)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": skin weights for " + std::to_string(w.vertex_count()) +
                                           " vertices, mesh has " + std::to_string(expected_vertices));
  for (int32_t v = 0; v < w.vertex_count(); ++v) {
    if (w.offsets[v + 1] < w.offsets[v])
      fail(PLEAT_ERROR_INVALID_ARGUMENT, vertex_name(source, v) + ": skin weight offsets decrease");
    double sum = 0.0;
    int32_t previous = -1;
    for (int32_t k = w.offsets[v]; k < w.offsets[v + 1]; ++k) {
      const int32_t j = w.joints[k];
      const double x = w.weights[k];
      if (j < 0 || j >= w.joint_count)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, vertex_name(source, v) + ": joint index " + std::to_string(j) +
                                               " out of range [0, " + std::to_string(w.joint_count) + ")");
      if (j <= previous)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, vertex_name(source, v) + ": joint " + std::to_string(j) +
                                               " repeated or not ascending (use normalize_skin_weights)");
      if (!std::isfinite(x) || x < 0.0)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, vertex_name(source, v) + ": weight " + std::to_string(x) +
                                               " for joint " + std::to_string(j) + " is not finite and >= 0");
      previous = j;
      sum += x;
    }
    if (!(std::abs(sum - 1.0) <= kSkinWeightSumTolerance))
      fail(PLEAT_ERROR_INVALID_ARGUMENT, vertex_name(source, v) + ": weights sum to " + std::to_string(sum) +
                                             ", not 1 (tolerance 1e-3; use normalize_skin_weights)");
  }
}

void normalize_skin_weights(SkinWeights* w, const std::string& source) {
  if (w->joints.size() != w->weights.size() || w->offsets.empty() || w->offsets.front() != 0 ||
      static_cast<size_t>(w->offsets.back()) != w->joints.size())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, source + ": skin weight arrays disagree in size");
  SkinWeights out;
  out.joint_count = w->joint_count;
  out.offsets.reserve(w->offsets.size());
  out.joints.reserve(w->joints.size());
  out.weights.reserve(w->weights.size());
  std::vector<std::pair<int32_t, double>> row;
  for (int32_t v = 0; v < w->vertex_count(); ++v) {
    if (w->offsets[v + 1] < w->offsets[v])
      fail(PLEAT_ERROR_INVALID_ARGUMENT, vertex_name(source, v) + ": skin weight offsets decrease");
    row.clear();
    for (int32_t k = w->offsets[v]; k < w->offsets[v + 1]; ++k) {
      const int32_t j = w->joints[k];
      const double x = w->weights[k];
      if (j < 0 || j >= w->joint_count)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, vertex_name(source, v) + ": joint index " + std::to_string(j) +
                                               " out of range [0, " + std::to_string(w->joint_count) + ")");
      if (!std::isfinite(x) || x < 0.0)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, vertex_name(source, v) + ": weight " + std::to_string(x) +
                                               " for joint " + std::to_string(j) + " is not finite and >= 0");
      row.emplace_back(j, x);
    }
    std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    double sum = 0.0;
    const size_t start = out.joints.size();
    for (const auto& [j, x] : row) {
      if (x == 0.0) continue;
      sum += x;
      if (out.joints.size() > start && out.joints.back() == j) {
        out.weights.back() += x;
      } else {
        out.joints.push_back(j);
        out.weights.push_back(x);
      }
    }
    if (!(sum > 0.0) || !std::isfinite(sum))
      fail(PLEAT_ERROR_INVALID_ARGUMENT, vertex_name(source, v) + ": no positive weight (sum " +
                                             std::to_string(sum) + "), cannot normalise");
    for (size_t k = start; k < out.weights.size(); ++k) out.weights[k] /= sum;
    out.offsets.push_back(static_cast<int32_t>(out.joints.size()));
  }
  *w = std::move(out);
}

SkinWeights skin_weights_from_dense(const Eigen::Ref<const Eigen::MatrixXd>& dense, double threshold) {
  SkinWeights w;
  w.joint_count = static_cast<int32_t>(dense.cols());
  w.offsets.reserve(static_cast<size_t>(dense.rows()) + 1);
  for (Eigen::Index v = 0; v < dense.rows(); ++v) {
    for (Eigen::Index j = 0; j < dense.cols(); ++j) {
      const double x = dense(v, j);
      // Keep non-finite and negative values so validation can name them.
      if (x > threshold || !std::isfinite(x) || x < 0.0) {
        w.joints.push_back(static_cast<int32_t>(j));
        w.weights.push_back(x);
      }
    }
    w.offsets.push_back(static_cast<int32_t>(w.joints.size()));
  }
  return w;
}

Eigen::MatrixXd dense_skin_weights(const SkinWeights& w) {
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(w.vertex_count(), w.joint_count);
  for (int32_t v = 0; v < w.vertex_count(); ++v)
    for (int32_t k = w.offsets[v]; k < w.offsets[v + 1]; ++k) dense(v, w.joints[k]) += w.weights[k];
  return dense;
}

SkinWeights truncate_skin_weights(const SkinWeights& w, int32_t k) {
  if (k < 1)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "truncate_skin_weights: k must be >= 1, got " + std::to_string(k));
  SkinWeights out;
  out.joint_count = w.joint_count;
  out.offsets.reserve(w.offsets.size());
  std::vector<int32_t> order;
  for (int32_t v = 0; v < w.vertex_count(); ++v) {
    const int32_t begin = w.offsets[v], n = w.offsets[v + 1] - begin;
    if (n <= k) {
      out.joints.insert(out.joints.end(), w.joints.begin() + begin, w.joints.begin() + begin + n);
      out.weights.insert(out.weights.end(), w.weights.begin() + begin, w.weights.begin() + begin + n);
    } else {
      order.resize(static_cast<size_t>(n));
      std::iota(order.begin(), order.end(), begin);
      std::partial_sort(order.begin(), order.begin() + k, order.end(), [&](int32_t a, int32_t b) {
        return w.weights[a] > w.weights[b] || (w.weights[a] == w.weights[b] && w.joints[a] < w.joints[b]);
      });
      order.resize(static_cast<size_t>(k));
      std::sort(order.begin(), order.end());  // slots ascend with joints
      double sum = 0.0;
      for (int32_t s : order) sum += w.weights[s];
      for (int32_t s : order) {
        out.joints.push_back(w.joints[s]);
        out.weights.push_back(sum > 0.0 ? w.weights[s] / sum : 1.0 / k);
      }
    }
    out.offsets.push_back(static_cast<int32_t>(out.joints.size()));
  }
  return out;
}

void skinning_matrices(const Transforms& pose_global, const Transforms& rest_global, SkinMatrices* out) {
  if (pose_global.size() != rest_global.size())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "skinning_matrices: " + std::to_string(pose_global.size()) +
                                           " pose transforms, " + std::to_string(rest_global.size()) +
                                           " rest");
  out->resize(pose_global.size());
  for (size_t j = 0; j < pose_global.size(); ++j) {
    // Rigid rest transforms: the inverse is [R^T | -R^T t].
    const Eigen::Matrix3d rt = rest_global[j].linear().transpose();
    const Eigen::Matrix3d r = pose_global[j].linear() * rt;
    (*out)[j].leftCols<3>() = r;
    (*out)[j].col(3) = pose_global[j].translation() - r * rest_global[j].translation();
  }
}

template <typename Scalar>
void linear_blend_skinning(const Points<Scalar>& rest, const SkinWeights& w, const SkinMatrices& matrices,
                           Points<Scalar>* posed) {
  if (w.vertex_count() != rest.rows())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "linear_blend_skinning: weights for " +
                                           std::to_string(w.vertex_count()) + " vertices, mesh has " +
                                           std::to_string(rest.rows()));
  check_matrices(matrices, w.joint_count);
  if (rest.rows() > 0 && posed->data() == rest.data())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "linear_blend_skinning: output aliases input");
  posed->resize(rest.rows(), 3);
  lbs_sparse_raw(rest.data(), w.vertex_count(), w, matrices, posed->data());
}

template <typename Scalar>
void linear_blend_skinning_dense(const Points<Scalar>& rest, const Eigen::Ref<const Eigen::MatrixXd>& weights,
                                 const SkinMatrices& matrices, Points<Scalar>* posed) {
  if (weights.rows() != rest.rows())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "linear_blend_skinning_dense: weights for " +
                                           std::to_string(weights.rows()) + " vertices, mesh has " +
                                           std::to_string(rest.rows()));
  check_matrices(matrices, static_cast<int32_t>(weights.cols()));
  if (rest.rows() > 0 && posed->data() == rest.data())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "linear_blend_skinning_dense: output aliases input");
  posed->resize(rest.rows(), 3);
  for (Eigen::Index v = 0; v < rest.rows(); ++v) {
    SkinMatrix blend = SkinMatrix::Zero();
    for (Eigen::Index j = 0; j < weights.cols(); ++j) {
      const double x = weights(v, j);
      if (x != 0.0) blend.noalias() += x * matrices[static_cast<size_t>(j)];
    }
    skin_vertex(rest.data() + 3 * v, blend, posed->data() + 3 * v);
  }
}

template <typename Scalar>
void skin_frames(const Points<Scalar>& rest, const SkinWeights& w, const Motion& motion, int64_t first,
                 int64_t count, SkinningWorkspace* ws, Scalar* out, size_t out_size) {
  const Skeleton& s = motion.skeleton;
  if (w.joint_count != s.joint_count())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "skin_frames: weights over " + std::to_string(w.joint_count) +
                                           " joints, skeleton has " + std::to_string(s.joint_count()));
  if (w.vertex_count() != rest.rows())
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "skin_frames: weights for " + std::to_string(w.vertex_count()) +
                                           " vertices, mesh has " + std::to_string(rest.rows()));
  if (first < 0 || count < 0 || first + count > motion.frame_count)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "skin_frames: frames [" + std::to_string(first) + ", " +
                                           std::to_string(first + count) + ") outside the motion's " +
                                           std::to_string(motion.frame_count));
  const size_t per_frame = static_cast<size_t>(rest.rows()) * 3;
  if (out_size < per_frame * static_cast<size_t>(count))
    fail(PLEAT_ERROR_BUFFER_TOO_SMALL, "skin_frames: buffer of " + std::to_string(out_size) +
                                           " values, need " +
                                           std::to_string(per_frame * static_cast<size_t>(count)));
  ws->rest_global = rest_transforms(s);  // once per call, not per frame
  for (int64_t f = first; f < first + count; ++f) {
    forward_kinematics(s, motion.frame(f), motion.root_translation.row(f).transpose(), &ws->pose_global);
    skinning_matrices(ws->pose_global, ws->rest_global, &ws->matrices);
    lbs_sparse_raw(rest.data(), w.vertex_count(), w, ws->matrices,
                   out + per_frame * static_cast<size_t>(f - first));
  }
}

#define PLEAT_SKINNING_INSTANTIATE(Scalar)                                                             \
  template void linear_blend_skinning<Scalar>(const Points<Scalar>&, const SkinWeights&,               \
                                              const SkinMatrices&, Points<Scalar>*);                   \
  template void linear_blend_skinning_dense<Scalar>(const Points<Scalar>&,                             \
                                                    const Eigen::Ref<const Eigen::MatrixXd>&,          \
                                                    const SkinMatrices&, Points<Scalar>*);             \
  template void skin_frames<Scalar>(const Points<Scalar>&, const SkinWeights&, const Motion&, int64_t, \
                                    int64_t, SkinningWorkspace*, Scalar*, size_t);
PLEAT_SKINNING_INSTANTIATE(float)
PLEAT_SKINNING_INSTANTIATE(double)
#undef PLEAT_SKINNING_INSTANTIATE

}  // namespace pleat
