// Golden test of the whole runtime: a tiny model (3 joints, code width 2, one
// layer per stack) with random weights, evaluated by an Instance and by an
// independent double-precision implementation written here from the
// definitions in docs/runtime.md (naive loops, no pleat kernels), at every
// stage, for a motion that turns, walks and bends every joint.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <vector>

#include "body/body.h"
#include "garment/garment.h"
#include "nn/gemm.h"
#include "runtime/binding.h"
#include "runtime/instance.h"
#include "runtime/model.h"
#include "support/kernel_paths.h"
#include "support/stage_outputs.h"

namespace {

using namespace pleat;
using namespace pleat::runtime;
using Mat = Eigen::MatrixXd;
using Vec3 = Eigen::Vector3d;

constexpr int kJoints = 3, kCode = 2, kWindow = 3, kFrames = 6;
constexpr double kFps = 30.0;
const double kRestJoints[kJoints][3] = {{0.0, 1.0, 0.0}, {0.0, 1.3, 0.0}, {0.3, 1.4, 0.0}};

// Deterministic weights in [-0.6, 0.6].
struct Lcg {
  uint64_t s = 12345;
  float next() {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<float>((s >> 40) * (1.0 / (1ull << 24)) * 1.2 - 0.6);
  }
  nn::MatrixRM matrix(Index r, Index c) {
    nn::MatrixRM m(r, c);
    for (Index i = 0; i < m.size(); ++i) m.data()[i] = next();
    return m;
  }
  nn::RowVector vector(Index n) { return matrix(1, n).row(0); }
};

nn::GraphAttentionLayer graph_layer(Lcg& rng, Index in, Index out, nn::AttentionVariant variant,
                                    nn::Activation act) {
  nn::GraphAttentionLayer l;
  l.variant = variant;
  l.merge = nn::HeadMerge::mean;
  l.activation = act;
  l.heads = 2;
  l.weight = rng.matrix(in, 2 * out);
  l.attention = rng.matrix(2, 2 * out);
  l.p = nn::RowVector(2);
  l.q = nn::RowVector(2);
  l.p << 1.3f, 0.8f;
  l.q << 0.6f, 1.1f;
  l.bias = rng.vector(out);
  return l;
}

std::shared_ptr<Model> tiny_model(nn::AttentionVariant variant) {
  Lcg rng;
  auto m = std::make_shared<Model>();
  m->source = "golden";
  m->skeleton = {{"hips", "spine", "arm"}, {-1, 0, 1}};
  m->shape = {{"height", 0.0f}};
  m->frame_rate = kFps;
  m->window_frames = kWindow;
  m->default_top_k = 2;
  m->body_features = {Feature::shape, Feature::rest_joint_distances};
  nn::Dense body;
  body.weight = rng.matrix(1 + kJoints, 3);
  body.bias = rng.vector(3);
  m->body_encoder.layers = {body};
  m->body_encoder.output_activation = nn::Activation::tanh();
  m->body_pool.weight = rng.matrix(6, kCode);
  m->body_pool.bias = rng.vector(kCode);
  m->garment_encoder.features = {Feature::rest_position, Feature::rest_normal, Feature::rest_joint_distances};
  m->garment_encoder.layers = {graph_layer(rng, 6 + kJoints, kCode, variant, nn::Activation::tanh())};
  m->motion_features = {Feature::joint_rotations_6d, Feature::root_velocity};
  nn::GruLayer gru;
  gru.w_ih = rng.matrix(6 * kJoints + 3, 3 * kCode);
  gru.w_hh = rng.matrix(kCode, 3 * kCode);
  gru.b_ih = rng.vector(3 * kCode);
  gru.b_hh = rng.vector(3 * kCode);
  m->motion_encoder.layers = {gru};
  m->skinning.weight = rng.matrix(kCode, kJoints);
  m->skinning.bias = rng.vector(kJoints);
  m->skinning_prior = 0.7f;
  m->blend.layers = {graph_layer(rng, kCode, 3, variant, nn::Activation::identity())};
  m->blend_scale = 0.05f;
  m->refinement.features = {Feature::velocity, Feature::normal, Feature::posed_joint_distances};
  m->refinement.layers = {graph_layer(rng, 6 + kJoints, 3, variant, nn::Activation::identity())};
  m->refinement_scale = 0.03f;
  validate_model(*m);
  return m;
}

Body chain_body() {
  Body b;
  b.source = "golden body";
  b.skeleton.names = {"hips", "spine", "arm"};
  b.skeleton.parents = {-1, 0, 1};
  b.skeleton.rest_translation.resize(kJoints, 3);
  b.skeleton.rest_translation << 0.0, 1.0, 0.0, 0.0, 0.3, 0.0, 0.3, 0.1, 0.0;
  b.skeleton.rest_rotation.assign(kJoints, Eigen::Quaterniond::Identity());
  b.rest.vertices.resize(5, 3);
  b.rest.vertices << -0.1, 0.9, 0.05, 0.1, 0.9, 0.05, -0.1, 1.3, 0.05, 0.1, 1.3, 0.05, 0.35, 1.4, 0.05;
  b.rest.triangles.resize(3, 3);
  b.rest.triangles << 0, 1, 2, 1, 3, 2, 3, 4, 2;
  b.weights.joint_count = kJoints;
  b.weights.offsets = {0, 1, 2, 4, 6, 7};
  b.weights.joints = {0, 0, 0, 1, 1, 2, 2};
  b.weights.weights = {1.0, 1.0, 0.4, 0.6, 0.3, 0.7, 1.0};
  b.shape = {{"height", 0.3, 0.0, 0.0, 1.0, ""}};
  validate_body(b, b.source);
  return b;
}

// A 3 x 3 vertex sheet in front of the body.
std::shared_ptr<const Garment> sheet() {
  Points3d v(9, 3);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      v.row(r * 3 + c) << -0.12 + 0.14 * c, 0.95 + 0.2 * r + 0.01 * c, 0.1 + 0.02 * r;
  Triangles t(8, 3);
  int k = 0;
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c) {
      const int a = r * 3 + c;
      t.row(k++) << a, a + 1, a + 3;
      t.row(k++) << a + 1, a + 4, a + 3;
    }
  return std::make_shared<const Garment>(build_garment(v, t, {}, "golden sheet"));
}

// ---------------------------------------------------------------- reference

Mat dense(const nn::MatrixRM& m) {
  return m.cast<double>();
}

double act(const nn::Activation& a, double x) {
  return a.kind == nn::ActivationKind::tanh ? std::tanh(x) : x;
}

// One graph-attention layer, naive (docs/nn.md's formulas).
Mat gat(const nn::GraphAttentionLayer& l, const Mat& v, const std::vector<std::vector<int>>& nbrs) {
  const int heads = l.heads, d = static_cast<int>(l.weight.cols()) / heads;
  const Mat w = dense(l.weight), a = dense(l.attention);
  const bool flexible = l.variant == nn::AttentionVariant::flexigat;
  const Mat z = v * w;
  Mat out = Mat::Zero(v.rows(), d);
  for (int i = 0; i < v.rows(); ++i) {
    for (int h = 0; h < heads; ++h) {
      const auto zi = z.row(i).segment(h * d, d);
      std::vector<double> e;
      for (int j : nbrs[i]) {
        double r = a.row(h).head(d).dot(zi) + a.row(h).tail(d).dot(z.row(j).segment(h * d, d));
        if (l.variant == nn::AttentionVariant::lgat) {
          double largest = 0;
          for (int k : nbrs[i]) largest = std::max(largest, z.row(k).segment(h * d, d).norm());
          r /= a.row(h).head(d).norm() * zi.norm() + a.row(h).tail(d).norm() * largest + l.lipschitz_epsilon;
        }
        e.push_back(r > 0 ? r : 0.2 * r);
      }
      const double top = *std::max_element(e.begin(), e.end());
      double sum = 0;
      for (double& x : e) sum += (x = std::exp(x - top));
      Eigen::RowVectorXd agg = Eigen::RowVectorXd::Zero(d);
      for (size_t k = 0; k < e.size(); ++k) agg += e[k] / sum * z.row(nbrs[i][k]).segment(h * d, d);
      const double p = flexible ? l.p[h] : 1.0, q = flexible ? l.q[h] : 1.0;
      out.row(i) += ((p - q) * zi + q * agg) / heads;
    }
    for (int c = 0; c < d; ++c) out(i, c) = act(l.activation, out(i, c) + l.bias[c]);
  }
  return out;
}

double sigmoid(double x) {
  return 1.0 / (1.0 + std::exp(-x));
}

Eigen::RowVectorXd gru(const nn::GruLayer& l, const Mat& steps) {
  const int hw = static_cast<int>(l.w_hh.rows());
  Eigen::RowVectorXd h = Eigen::RowVectorXd::Zero(hw);
  for (int t = 0; t < steps.rows(); ++t) {
    const Eigen::RowVectorXd gi = steps.row(t) * dense(l.w_ih) + l.b_ih.cast<double>();
    const Eigen::RowVectorXd gh = h * dense(l.w_hh) + l.b_hh.cast<double>();
    Eigen::RowVectorXd next(hw);
    for (int k = 0; k < hw; ++k) {
      const double r = sigmoid(gi[k] + gh[k]), z = sigmoid(gi[hw + k] + gh[hw + k]);
      const double n = std::tanh(gi[2 * hw + k] + r * gh[2 * hw + k]);
      next[k] = (1 - z) * n + z * h[k];
    }
    h = next;
  }
  return h;
}

struct Poses {
  std::vector<float> rotations, roots;  // x y z w per joint; xyz per frame
  Eigen::Quaterniond q(int f, int j) const {
    const float* r = &rotations[(f * kJoints + j) * 4];
    return Eigen::Quaterniond(r[3], r[0], r[1], r[2]).normalized();
  }
  Vec3 root(int f) const { return Vec3(roots[f * 3], roots[f * 3 + 1], roots[f * 3 + 2]); }
};

// The root turns about Y and tilts, the others bend; the root walks.
Poses motion() {
  Poses p;
  for (int f = 0; f < kFrames; ++f) {
    const Eigen::Quaterniond qs[kJoints] = {
        Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * f, Vec3::UnitY()) * Eigen::AngleAxisd(0.1, Vec3::UnitX())),
        Eigen::Quaterniond(Eigen::AngleAxisd(0.2 * f, Vec3(0.3, 0.1, 1.0).normalized())),
        Eigen::Quaterniond(Eigen::AngleAxisd(-0.25 * f, Vec3::UnitX()))};
    for (const auto& q : qs)
      p.rotations.insert(p.rotations.end(), {float(q.x()), float(q.y()), float(q.z()), float(q.w())});
    p.roots.insert(p.roots.end(), {0.04f * f, 1.0f + 0.01f * f, -0.03f * f});
  }
  return p;
}

Mat vertex_normals_ref(const Mat& x, const Triangles& t) {
  Mat n = Mat::Zero(x.rows(), 3);
  for (int f = 0; f < t.rows(); ++f) {
    const Vec3 a = x.row(t(f, 0)), b = x.row(t(f, 1)), c = x.row(t(f, 2));
    const Vec3 cr = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) n.row(t(f, k)) += cr.transpose();
  }
  for (int v = 0; v < n.rows(); ++v) n.row(v).normalize();
  return n;
}

// Global joint transforms of frame f (identity rest rotations).
std::vector<Eigen::Affine3d> fk(const Body& body, const Poses& p, int f) {
  std::vector<Eigen::Affine3d> g(kJoints);
  for (int j = 0; j < kJoints; ++j) {
    Eigen::Affine3d local = Eigen::Affine3d::Identity();
    local.linear() = p.q(f, j).toRotationMatrix();
    local.translation() = j == 0 ? p.root(f) : Vec3(body.skeleton.rest_translation.row(j).transpose());
    g[j] = j == 0 ? local : g[body.skeleton.parents[j]] * local;
  }
  return g;
}

Eigen::Matrix3d heading_ref(const Poses& p, int f) {
  const Vec3 z = p.q(f, 0).toRotationMatrix().col(2);
  return Eigen::AngleAxisd(std::atan2(z.x(), z.z()), Vec3::UnitY()).toRotationMatrix();
}

// (I + L)^{-1} d, L over the triangles' edges weighted by (h / length)²,
// dense; h = 0 leaves d as it is.
Mat filtered(const Mat& d, const Mat& rest, const Triangles& triangles, double h) {
  if (h == 0.0) return d;
  std::set<std::pair<int, int>> edges;
  for (int f = 0; f < triangles.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles(f, k), b = triangles(f, (k + 1) % 3);
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  Mat a = Mat::Identity(rest.rows(), rest.rows());
  for (const auto& [i, j] : edges) {
    const double w = std::pow(h / (rest.row(i) - rest.row(j)).norm(), 2);
    a(i, i) += w;
    a(j, j) += w;
    a(i, j) -= w;
    a(j, i) -= w;
  }
  return a.ldlt().solve(d);
}

// All frames of the motion at `stage`, N x 3 per frame.
std::vector<Mat> reference(const Model& m, const Garment& g, const Body& body, const Poses& p, Stage stage) {
  const int n = g.rest.vertex_count();
  std::vector<std::vector<int>> nbrs(n);
  for (int i = 0; i < n; ++i) {
    for (int k = g.graph.offsets[i]; k < g.graph.offsets[i + 1]; ++k) nbrs[i].push_back(g.graph.indices[k]);
    nbrs[i].push_back(i);
  }
  Mat rest_j(kJoints, 3);
  for (int j = 0; j < kJoints; ++j) rest_j.row(j) << kRestJoints[j][0], kRestJoints[j][1], kRestJoints[j][2];

  // Body code, over body vertices 0, k, 2k, ...
  const int stride = m.body_vertex_stride, rows = (body.vertex_count() + stride - 1) / stride;
  Mat h(rows, 3);
  for (int r = 0; r < rows; ++r) {
    const int v = r * stride;
    Eigen::RowVectorXd x(1 + kJoints);
    x[0] = 0.3;  // the body's height
    for (int j = 0; j < kJoints; ++j) x[1 + j] = (body.rest.vertices.row(v) - rest_j.row(j)).norm();
    const Eigen::RowVectorXd y =
        x * dense(m.body_encoder.layers[0].weight) + m.body_encoder.layers[0].bias.cast<double>();
    for (int c = 0; c < 3; ++c) h(r, c) = std::tanh(y[c]);
  }
  Eigen::RowVectorXd pooled(6);
  pooled << h.colwise().mean(), h.colwise().maxCoeff();
  Eigen::RowVectorXd code = pooled * dense(m.body_pool.weight) + m.body_pool.bias.cast<double>();
  for (int c = 0; c < kCode; ++c) code[c] = std::tanh(code[c]);

  // Garment code G ⊙ b.
  const Mat rest = g.rest.vertices;
  const Mat rest_n = vertex_normals_ref(rest, g.rest.triangles);
  Mat gx(n, 6 + kJoints);
  for (int v = 0; v < n; ++v) {
    gx.row(v).head(3) = rest.row(v) - rest_j.row(0);
    gx.row(v).segment(3, 3) = rest_n.row(v);
    for (int j = 0; j < kJoints; ++j) gx(v, 6 + j) = (rest.row(v) - rest_j.row(j)).norm();
  }
  Mat gb = gat(m.garment_encoder.layers[0], gx, nbrs);
  for (int v = 0; v < n; ++v) gb.row(v) = gb.row(v).cwiseProduct(code);

  // Skinning prior: the body weights within the prior's radius, weighted
  // 1 - (d / r)², else the nearest body vertex's.
  Mat prior(n, kJoints);
  const Eigen::MatrixXd body_w = dense_skin_weights(body.weights);
  const double r = m.skinning_prior_radius;
  for (int v = 0; v < n; ++v) {
    int best = 0;
    Eigen::RowVectorXd near = Eigen::RowVectorXd::Zero(kJoints);
    double total = 0.0;
    for (int b = 0; b < body.vertex_count(); ++b) {
      const double d = (body.rest.vertices.row(b) - rest.row(v)).norm();
      if (d < (body.rest.vertices.row(best) - rest.row(v)).norm()) best = b;
      if (d < r) near += (1 - d * d / (r * r)) * body_w.row(b), total += 1 - d * d / (r * r);
    }
    const Eigen::RowVectorXd w =
        total > 0 ? Eigen::RowVectorXd(near / total) : Eigen::RowVectorXd(body_w.row(best));
    for (int j = 0; j < kJoints; ++j)
      prior(v, j) = m.skinning_prior * std::log(w[j] + m.skinning_prior_floor);
  }

  Poses rest_pose;
  for (int j = 0; j < kJoints; ++j) rest_pose.rotations.insert(rest_pose.rotations.end(), {0, 0, 0, 1});
  rest_pose.roots = {0.0f, 1.0f, 0.0f};
  const std::vector<Eigen::Affine3d> rest_g = fk(body, rest_pose, 0);
  std::vector<Mat> skinned, out;
  for (int t = 0; t < kFrames; ++t) {
    const Eigen::Matrix3d ht = heading_ref(p, t);
    Mat window(kWindow, 6 * kJoints + 3);
    for (int w = 0; w < kWindow; ++w) {
      const int f = std::max(0, t - kWindow + 1 + w);
      for (int j = 0; j < kJoints; ++j) {
        const Eigen::Matrix3d r = j == 0 ? Eigen::Matrix3d(ht.transpose() * p.q(f, 0).toRotationMatrix())
                                         : p.q(f, j).toRotationMatrix();
        window.row(w).segment(6 * j, 3) = r.col(0).transpose();
        window.row(w).segment(6 * j + 3, 3) = r.col(1).transpose();
      }
      window.row(w).tail(3) = (ht.transpose() * (p.root(f) - p.root(std::max(0, f - 1))) * kFps).transpose();
    }
    const Eigen::RowVectorXd q = gru(m.motion_encoder.layers[0], window);
    Mat fused = gb;
    for (int v = 0; v < n; ++v) fused.row(v) = fused.row(v).cwiseProduct(q);
    Mat logits = fused * dense(m.skinning.weight) + prior;
    logits.rowwise() += m.skinning.bias.cast<double>();
    Mat offsets = stage == Stage::skinning ? Mat::Zero(n, 3) : Mat(gat(m.blend.layers[0], fused, nbrs));
    const std::vector<Eigen::Affine3d> pose_g = fk(body, p, t);
    Mat x(n, 3), displacement(n, 3);  // LBS of T̄, and what the blend shapes add to it
    for (int v = 0; v < n; ++v) {
      // Top 2 of the 3 joints, softmax over those two.
      int order[kJoints] = {0, 1, 2};
      std::sort(order, order + kJoints, [&](int a, int b) {
        return logits(v, a) > logits(v, b) || (logits(v, a) == logits(v, b) && a < b);
      });
      const double e0 = 1.0, e1 = std::exp(logits(v, order[1]) - logits(v, order[0]));
      const Vec3 blend = m.blend_scale * offsets.row(v).transpose();
      Vec3 sum = Vec3::Zero(), moved = Vec3::Zero();
      for (int i = 0; i < 2; ++i) {
        const int j = order[i];
        const Eigen::Affine3d s = pose_g[j] * rest_g[j].inverse();
        sum += (i == 0 ? e0 : e1) / (e0 + e1) * (s * Vec3(rest.row(v).transpose()));
        moved += (i == 0 ? e0 : e1) / (e0 + e1) * (s.linear() * blend);
      }
      x.row(v) = sum.transpose();
      displacement.row(v) = moved.transpose();
    }
    x += filtered(displacement, rest, g.rest.triangles, m.offset_filter_length);
    skinned.push_back(x);
    if (stage != Stage::refinement) {
      out.push_back(x);
      continue;
    }
    const Mat normals = vertex_normals_ref(x, g.rest.triangles);
    Mat rx(n, 6 + kJoints);
    for (int v = 0; v < n; ++v) {
      const Vec3 vel = t == 0 ? Vec3::Zero() : Vec3((x.row(v) - skinned[t - 1].row(v)).transpose() * kFps);
      rx.row(v).head(3) = (ht.transpose() * vel).transpose();
      rx.row(v).segment(3, 3) = (ht.transpose() * normals.row(v).transpose()).transpose();
      for (int j = 0; j < kJoints; ++j)
        rx(v, 6 + j) = (x.row(v).transpose() - pose_g[j].translation()).norm();
    }
    const Mat delta =
        filtered(gat(m.refinement.layers[0], rx, nbrs), rest, g.rest.triangles, m.offset_filter_length);
    Mat final_x = x;
    for (int v = 0; v < n; ++v)
      final_x.row(v) += m.refinement_scale * (ht * delta.row(v).transpose()).transpose();
    out.push_back(final_x);
  }
  return out;
}

void expect_matches(nn::AttentionVariant variant, int32_t body_vertex_stride = 1,
                    float offset_filter_length = 0.0f, float prior_radius = 0.0f,
                    float prior_floor = kDefaultSkinningPriorFloor) {
  const std::shared_ptr<Model> model = tiny_model(variant);
  model->body_vertex_stride = body_vertex_stride;
  model->offset_filter_length = offset_filter_length;
  model->skinning_prior_radius = prior_radius;
  model->skinning_prior_floor = prior_floor;
  const Body body = chain_body();
  const auto garment = sheet();
  const Poses p = motion();
  const PoseSequence poses{p.rotations.data(), p.roots.data(), kFrames, kJoints, kFps};
  // Every kernel path this CPU runs (nn/kernel_path.h) meets the same reference.
  pleat_test::for_each_kernel_path([&](nn::KernelPath) {
    InstanceOptions options;
    Instance instance(model, garment, body, options);
    ASSERT_EQ(instance.top_k(), 2);
    const int n = instance.vertex_count();
    for (Stage stage : {Stage::skinning, Stage::blend_shapes, Stage::refinement}) {
      std::vector<float> got(size_t(kFrames) * n * 3);
      EvaluateOutputs out;
      out.positions = {got.data(), size_t(n) * 3};
      instance.evaluate(poses, 0, kFrames, stage, out);
      const std::vector<Mat> want = reference(*model, *garment, body, p, stage);
      double largest = 0.0, moved = 0.0;
      for (int f = 0; f < kFrames; ++f)
        for (int v = 0; v < n; ++v)
          for (int k = 0; k < 3; ++k) {
            largest = std::max(largest, std::abs(got[(size_t(f) * n + v) * 3 + k] - want[f](v, k)));
            moved = std::max(moved, std::abs(want[f](v, k) - garment->rest.vertices(v, k)));
          }
      EXPECT_LT(largest, 2e-6) << "stage " << int(stage);
      EXPECT_GT(moved, 0.1) << "the motion moves the garment";
    }
  });
}

TEST(RuntimeGolden, FlexiGatModelMatchesIndependentReference) {
  expect_matches(nn::AttentionVariant::flexigat);
}
TEST(RuntimeGolden, GatModelMatchesIndependentReference) {
  expect_matches(nn::AttentionVariant::gat);
}
TEST(RuntimeGolden, LgatModelMatchesIndependentReference) {
  expect_matches(nn::AttentionVariant::lgat);
}

// The body code pools over vertices 0, 2, 4 of the 5-vertex body.
TEST(RuntimeGolden, BodyVertexStrideMatchesIndependentReference) {
  expect_matches(nn::AttentionVariant::flexigat, 2);
}

// h = 0.1 m weighs the sheet's 0.14–0.2 m edges at 0.25–0.5: the filter
// changes every offset.
TEST(RuntimeGolden, OffsetFilterMatchesIndependentReference) {
  expect_matches(nn::AttentionVariant::flexigat, 1, 0.1f);
}

// A soft prior: r = 0.25 m reaches two to four of the chain's body vertices
// from each sheet vertex, the floor puts an absent joint at log(0.01).
TEST(RuntimeGolden, SoftSkinningPriorMatchesIndependentReference) {
  expect_matches(nn::AttentionVariant::flexigat, 1, 0.0f, 0.25f, 0.01f);
  // A radius that reaches no body vertex from some sheet vertices: those
  // fall back to the nearest vertex's weights.
  expect_matches(nn::AttentionVariant::flexigat, 1, 0.0f, 0.06f, 0.01f);
}

// The prior's radius mixes the weights of the body vertices it reaches, by
// hand: sheet vertex 8 at (0.16, 1.37, 0.14) is 0.545, 0.482, 0.284, 0.129
// and 0.212 m from body vertices 0-4 (hips, hips, hips/spine 0.4/0.6,
// spine/arm 0.3/0.7, arm). With r = 0.5 m vertices 1-4 count, with
// 1 - (d/r)² = 0.0696, 0.6776, 0.9336, 0.8196: hips 0.1362, spine 0.2746,
// arm 0.5892. The nearest, vertex 3, has no hips at all.
TEST(RuntimeGolden, SoftSkinningPriorAveragesTheBodyWithinItsRadius) {
  const Body body = chain_body();
  const auto garment = sheet();
  std::shared_ptr<Model> model = tiny_model(nn::AttentionVariant::flexigat);
  model->skinning_prior = 1.0f;
  model->skinning_prior_floor = 0.01f;
  model->skinning_prior_radius = 0.0f;
  const nn::MatrixRM nearest = bind_inputs(*model, *garment, body)->prior;
  model->skinning_prior_radius = 0.5f;
  const nn::MatrixRM soft = bind_inputs(*model, *garment, body)->prior;
  EXPECT_NEAR(nearest(8, 0), std::log(0.01), 1e-5) << "hips absent: at the floor";
  EXPECT_NEAR(nearest(8, 2), std::log(0.71), 1e-5);
  EXPECT_NEAR(soft(8, 0), std::log(0.1362 + 0.01), 1e-3) << "hips within reach of training";
  EXPECT_NEAR(soft(8, 1), std::log(0.2746 + 0.01), 1e-3);
  EXPECT_NEAR(soft(8, 2), std::log(0.5892 + 0.01), 1e-3);
}

// The encoder's input rows are body vertices 0, 2, 4 with a stride of 2 (the
// tiny model's output hardly depends on its body code, so the reference
// comparison above alone could not tell strides apart).
TEST(RuntimeGolden, BodyVertexStrideSelectsEveryKthVertex) {
  const Body body = chain_body();
  const auto garment = sheet();
  std::shared_ptr<Model> all = tiny_model(nn::AttentionVariant::flexigat);
  std::shared_ptr<Model> strided = tiny_model(nn::AttentionVariant::flexigat);
  strided->body_vertex_stride = 2;
  const nn::MatrixRM every = bind_inputs(*all, *garment, body)->body_input;
  const nn::MatrixRM some = bind_inputs(*strided, *garment, body)->body_input;
  ASSERT_EQ(every.rows(), 5);
  ASSERT_EQ(some.rows(), 3);
  for (int r = 0; r < 3; ++r) EXPECT_EQ(some.row(r), every.row(2 * r)) << "row " << r;
  EXPECT_NE(every.row(1), every.row(0));
}

// Each stage adds to the one before: a model whose blend and refinement
// heads are scaled to zero gives the skinning result at every stage.
TEST(RuntimeGolden, ZeroScaledHeadsReduceToSkinning) {
  std::shared_ptr<Model> model = tiny_model(nn::AttentionVariant::flexigat);
  model->blend_scale = 0.0f;
  model->refinement_scale = 0.0f;
  const Body body = chain_body();
  const auto garment = sheet();
  const Poses p = motion();
  Instance instance(model, garment, body, InstanceOptions{});
  const PoseSequence poses{p.rotations.data(), p.roots.data(), kFrames, kJoints, kFps};
  EXPECT_EQ(pleat_test::evaluate_stage(instance, poses, kFrames, Stage::skinning),
            pleat_test::evaluate_stage(instance, poses, kFrames, Stage::refinement));
}

}  // namespace
