// Skin weights and linear blend skinning against hand-computed cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "body/skinning.h"
#include "core/error.h"
#include "runtime/frame_features.h"
#include "support/expect_error.h"

using pleat::Points3d;
using pleat::SkinWeights;

namespace {

using pleat_test::expect_error;

// Root at the origin, "tip" 1 m along +X.
pleat::Skeleton two_joint_chain() {
  pleat::Skeleton s;
  s.names = {"root", "tip"};
  s.parents = {-1, 0};
  s.rest_translation.resize(2, 3);
  s.rest_translation << 0, 0, 0, 1, 0, 0;
  s.rest_rotation.assign(2, Eigen::Quaterniond::Identity());
  return s;
}

Eigen::Quaterniond about_z(double degrees) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(degrees * M_PI / 180.0, Eigen::Vector3d::UnitZ()));
}

SkinWeights weights_of(int joints, const std::vector<std::vector<std::pair<int, double>>>& rows) {
  SkinWeights w;
  w.joint_count = joints;
  for (const auto& row : rows) {
    for (const auto& [j, x] : row) {
      w.joints.push_back(j);
      w.weights.push_back(x);
    }
    w.offsets.push_back(static_cast<int32_t>(w.joints.size()));
  }
  return w;
}

// A random skeleton (with non-identity rest rotations), mesh and weights.
struct RandomRig {
  pleat::Skeleton skeleton;
  Points3d rest;
  SkinWeights weights;
};

RandomRig random_rig(int joints, int vertices, int influences, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  RandomRig r;
  pleat::Skeleton& s = r.skeleton;
  s.rest_translation.resize(joints, 3);
  for (int j = 0; j < joints; ++j) {
    s.names.push_back("j" + std::to_string(j));
    s.parents.push_back(j == 0 ? -1 : static_cast<int32_t>(rng() % static_cast<unsigned>(j)));
    s.rest_translation.row(j) << u(rng), u(rng), u(rng);
    s.rest_rotation.push_back(Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized());
  }
  r.rest.resize(vertices, 3);
  for (int v = 0; v < vertices; ++v) r.rest.row(v) << u(rng), u(rng), u(rng);
  r.weights.joint_count = joints;
  for (int v = 0; v < vertices; ++v) {
    for (int k = 0; k < influences; ++k) {
      r.weights.joints.push_back(static_cast<int32_t>(rng() % static_cast<unsigned>(joints)));
      r.weights.weights.push_back(0.05 + std::abs(u(rng)));
    }
    r.weights.offsets.push_back(static_cast<int32_t>(r.weights.joints.size()));
  }
  pleat::normalize_skin_weights(&r.weights, "random");  // merges repeats, sorts, sums to 1
  return r;
}

pleat::Quaternions random_pose(int joints, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  pleat::Quaternions q;
  for (int j = 0; j < joints; ++j)
    q.push_back(Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized());
  return q;
}

}  // namespace

TEST(Skinning, TwoJointChainByHand) {
  const pleat::Skeleton s = two_joint_chain();
  pleat::validate_skeleton(s, "chain");
  // The tip turns 90 degrees about Z; the root stays.
  const pleat::Quaternions pose = {Eigen::Quaterniond::Identity(), about_z(90)};
  pleat::Transforms global;
  pleat::forward_kinematics(s, pose.data(), Eigen::Vector3d::Zero(), &global);
  EXPECT_LT((global[1].translation() - Eigen::Vector3d(1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((global[1] * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(1, 1, 0)).norm(), 1e-15);

  Points3d rest(4, 3);
  rest << 0.5, 0, 0,  // root only: stays
      2, 0, 0,        // tip only: (1, 0, 0) + Rz90 (1, 0, 0) = (1, 1, 0)
      1.5, 0, 0,      // half/half: 0.5 (1.5, 0, 0) + 0.5 (1, 0.5, 0) = (1.25, 0.25, 0)
      1.5, 0.2, 0.3;  // tip only: (1, 0, 0) + Rz90 (0.5, 0.2, 0.3) = (0.8, 0.5, 0.3)
  const SkinWeights w = weights_of(2, {{{0, 1.0}}, {{1, 1.0}}, {{0, 0.5}, {1, 0.5}}, {{1, 1.0}}});
  pleat::validate_skin_weights(w, 4, "chain");
  pleat::SkinMatrices m;
  pleat::skinning_matrices(global, pleat::rest_transforms(s), &m);
  Points3d posed;
  pleat::linear_blend_skinning(rest, w, m, &posed);
  Points3d expected(4, 3);
  expected << 0.5, 0, 0, 1, 1, 0, 1.25, 0.25, 0, 0.8, 0.5, 0.3;
  EXPECT_LT((posed - expected).cwiseAbs().maxCoeff(), 1e-14) << posed;

  // The root turned as well (both joints 90 degrees: the tip ends up pointing -X).
  const pleat::Quaternions pose2 = {about_z(90), about_z(90)};
  pleat::forward_kinematics(s, pose2.data(), Eigen::Vector3d(0, 0, 1), &global);
  pleat::skinning_matrices(global, pleat::rest_transforms(s), &m);
  pleat::linear_blend_skinning(rest, w, m, &posed);
  // Vertex 1: root at (0,0,1), tip at (0,1,1), tip frame rotated 180: (2,0,0) -> (-1, 1, 1).
  EXPECT_LT((posed.row(1) - Eigen::RowVector3d(-1, 1, 1)).norm(), 1e-14);
  // Vertex 0: root frame rotated 90: (0.5,0,0) -> (0, 0.5, 1).
  EXPECT_LT((posed.row(0) - Eigen::RowVector3d(0, 0.5, 1)).norm(), 1e-14);
}

TEST(Skinning, RestPoseReproducesRestMesh) {
  const RandomRig r = random_rig(12, 500, 4, 7);
  pleat::validate_skin_weights(r.weights, 500, "random");
  const pleat::Transforms rest = pleat::rest_transforms(r.skeleton);
  pleat::SkinMatrices m;
  pleat::skinning_matrices(rest, rest, &m);
  Points3d posed;
  pleat::linear_blend_skinning(r.rest, r.weights, m, &posed);
  EXPECT_LT((posed - r.rest).cwiseAbs().maxCoeff(), 1e-12);
  // Float mesh: rounding of float only.
  const pleat::Points3f rest_f = r.rest.cast<float>();
  pleat::Points3f posed_f;
  pleat::linear_blend_skinning(rest_f, r.weights, m, &posed_f);
  EXPECT_LT((posed_f - rest_f).cwiseAbs().maxCoeff(), 1e-6f);
}

TEST(Skinning, DenseAndTopKAgree) {
  const RandomRig r = random_rig(10, 300, 6, 11);
  const pleat::Quaternions pose = random_pose(10, 3);
  pleat::Transforms global;
  pleat::forward_kinematics(r.skeleton, pose.data(), Eigen::Vector3d(0.1, 0.2, 0.3), &global);
  pleat::SkinMatrices m;
  pleat::skinning_matrices(global, pleat::rest_transforms(r.skeleton), &m);
  Points3d sparse, dense, top;
  pleat::linear_blend_skinning(r.rest, r.weights, m, &sparse);
  pleat::linear_blend_skinning_dense(r.rest, pleat::dense_skin_weights(r.weights), m, &dense);
  const int32_t k = r.weights.max_influences();
  const SkinWeights truncated = pleat::truncate_skin_weights(r.weights, k);
  pleat::linear_blend_skinning(r.rest, truncated, m, &top);
  EXPECT_TRUE(sparse == dense);  // bit-identical
  EXPECT_TRUE(sparse == top);
  EXPECT_TRUE(pleat::truncate_skin_weights(r.weights, k + 3).weights == r.weights.weights);
  // Round trip through the dense matrix.
  const SkinWeights back = pleat::skin_weights_from_dense(pleat::dense_skin_weights(r.weights));
  EXPECT_EQ(back.joints, r.weights.joints);
  EXPECT_EQ(back.weights, r.weights.weights);
}

TEST(Skinning, TopKKeepsLargestAndRenormalises) {
  const SkinWeights w = weights_of(5, {{{0, 0.1}, {1, 0.4}, {2, 0.2}, {4, 0.3}}, {{3, 1.0}}});
  const SkinWeights t = pleat::truncate_skin_weights(w, 2);
  pleat::validate_skin_weights(t, 2, "top2");
  ASSERT_EQ(t.offsets, (std::vector<int32_t>{0, 2, 3}));
  EXPECT_EQ(t.joints, (std::vector<int32_t>{1, 4, 3}));
  EXPECT_NEAR(t.weights[0], 0.4 / 0.7, 1e-15);
  EXPECT_NEAR(t.weights[1], 0.3 / 0.7, 1e-15);
  EXPECT_EQ(t.weights[2], 1.0);
  expect_error([&] { pleat::truncate_skin_weights(w, 0); }, PLEAT_ERROR_INVALID_ARGUMENT, "k must be >= 1");
}

TEST(Skinning, ValidationNamesVertexAndSum) {
  const auto I = PLEAT_ERROR_INVALID_ARGUMENT;
  expect_error(
      [] {
        pleat::validate_skin_weights(weights_of(2, {{{0, 1.0}}, {{0, 0.5}, {1, 0.4}}}), 2, "w");
      },
      I, "w: vertex 1: weights sum to 0.900000");
  expect_error(
      [] {
        pleat::validate_skin_weights(weights_of(2, {{{0, 0.5}, {2, 0.5}}}), 1, "w");
      },
      I, "w: vertex 0: joint index 2 out of range");
  expect_error(
      [] {
        pleat::validate_skin_weights(weights_of(2, {{{0, 1.5}, {1, -0.5}}}), 1, "w");
      },
      I, "w: vertex 0: weight -0.5");
  expect_error(
      [] {
        pleat::validate_skin_weights(weights_of(2, {{{0, NAN}, {1, 1.0}}}), 1, "w");
      },
      I, "w: vertex 0: weight nan");
  expect_error(
      [] {
        pleat::validate_skin_weights(weights_of(2, {{{1, 0.5}, {0, 0.5}}}), 1, "w");
      },
      I, "not ascending");
  expect_error(
      [] {
        pleat::validate_skin_weights(weights_of(2, {{{0, 1.0}}}), 3, "w");
      },
      I, "weights for 1 vertices, mesh has 3");
  // Within 1e-3 passes.
  pleat::validate_skin_weights(weights_of(2, {{{0, 0.5}, {1, 0.5009}}}), 1, "w");
  // normalize: merges, sorts, drops zeros, rescales; a vertex with nothing is an error.
  SkinWeights w = weights_of(3, {{{2, 1.0}, {0, 2.0}, {2, 1.0}, {1, 0.0}}});
  pleat::normalize_skin_weights(&w, "load");
  EXPECT_EQ(w.joints, (std::vector<int32_t>{0, 2}));
  EXPECT_EQ(w.weights, (std::vector<double>{0.5, 0.5}));
  SkinWeights empty = weights_of(3, {{{0, 1.0}}, {{1, 0.0}}});
  expect_error([&] { pleat::normalize_skin_weights(&empty, "load"); }, I,
               "load: vertex 1: no positive weight");
}

TEST(Skinning, BatchedFramesMatchSingleFrames) {
  const RandomRig r = random_rig(8, 200, 4, 5);
  pleat::Motion motion;
  motion.skeleton = r.skeleton;
  motion.frame_count = 5;
  motion.root_translation.resize(5, 3);
  for (int f = 0; f < 5; ++f) {
    const pleat::Quaternions pose = random_pose(8, 100 + static_cast<unsigned>(f));
    motion.rotations.insert(motion.rotations.end(), pose.begin(), pose.end());
    motion.root_translation.row(f) = r.skeleton.rest_translation.row(0) + Eigen::RowVector3d(0.1 * f, 0, 0);
  }
  pleat::SkinningWorkspace ws;
  std::vector<float> out(3 * 200 * 3);
  const pleat::Points3f rest_f = r.rest.cast<float>();
  pleat::skin_frames(rest_f, r.weights, motion, 1, 3, &ws, out.data(), out.size());
  for (int f = 1; f < 4; ++f) {
    pleat::Transforms global;
    pleat::forward_kinematics(r.skeleton, motion.frame(f), motion.root_translation.row(f).transpose(),
                              &global);
    pleat::SkinMatrices m;
    pleat::skinning_matrices(global, pleat::rest_transforms(r.skeleton), &m);
    pleat::Points3f posed;
    pleat::linear_blend_skinning(rest_f, r.weights, m, &posed);
    for (int i = 0; i < 600; ++i) ASSERT_EQ(out[static_cast<size_t>((f - 1) * 600 + i)], posed.data()[i]);
  }
  expect_error([&] { pleat::skin_frames(rest_f, r.weights, motion, 0, 3, &ws, out.data(), out.size() - 1); },
               PLEAT_ERROR_BUFFER_TOO_SMALL, "need 1800");
  expect_error([&] { pleat::skin_frames(rest_f, r.weights, motion, 3, 3, &ws, out.data(), out.size()); },
               PLEAT_ERROR_INVALID_ARGUMENT, "outside the motion's 5");
}

// The runtime's learned weights: top-k of the logits against a full sort
// (largest first, ties to the lower joint) and a double-precision softmax
// over the kept ones, with ties at the cut (logits on a coarse grid).
TEST(Skinning, RuntimeTopKSoftmaxMatchesSortedReference) {
  std::mt19937 rng(7);
  for (int32_t joints : {1, 5, 31, 300}) {
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<float> logits(static_cast<size_t>(joints));
      std::uniform_int_distribution<int> grid(-8, 8);
      std::normal_distribution<float> normal(0.0f, 3.0f);
      for (float& l : logits) l = trial % 2 ? 0.5f * static_cast<float>(grid(rng)) : normal(rng);
      for (int32_t k : {1, 2, 8, 16, joints}) {
        if (k > joints) continue;
        std::vector<int32_t> order(static_cast<size_t>(joints));
        std::iota(order.begin(), order.end(), 0);
        std::stable_sort(order.begin(), order.end(),
                         [&](int32_t a, int32_t b) { return logits[a] > logits[b]; });
        std::vector<int32_t> expected_joints(order.begin(), order.begin() + k);
        std::sort(expected_joints.begin(), expected_joints.end());
        double sum = 0.0;
        for (int32_t j : expected_joints) sum += std::exp(double(logits[j]) - double(logits[order[0]]));

        std::vector<float> weights(static_cast<size_t>(k));
        std::vector<int32_t> chosen(static_cast<size_t>(k));
        pleat::runtime::top_k_softmax(logits.data(), joints, k, weights.data(), chosen.data());
        std::vector<int32_t> chosen_sorted = chosen;
        std::sort(chosen_sorted.begin(), chosen_sorted.end());
        ASSERT_EQ(chosen_sorted, expected_joints) << "S " << joints << " k " << k << " trial " << trial;
        for (int32_t i = 0; i < k; ++i) {
          const double expected = std::exp(double(logits[chosen[i]]) - double(logits[order[0]])) / sum;
          EXPECT_NEAR(weights[i], expected, 1e-6) << "S " << joints << " k " << k << " joint " << chosen[i];
        }
      }
    }
  }
}
