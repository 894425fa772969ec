// Error metrics against answers known by construction or by hand.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <random>

#include "core/error.h"
#include "core/geometry.h"
#include "core/topology.h"
#include "metrics/body_penetration.h"
#include "metrics/curvature.h"
#include "metrics/metrics.h"
#include "metrics/self_collision.h"
#include "support/expect_error.h"
#include "support/test_support.h"

namespace pleat {
namespace {

constexpr double kPi = 3.14159265358979323846;

Triangles triangles_of(const pleat_test::SimpleMesh& m) {
  Triangles t(static_cast<Eigen::Index>(m.triangle_count()), 3);
  for (size_t i = 0; i < m.triangles.size(); ++i)
    t(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3)) =
        static_cast<int32_t>(m.triangles[i]);
  return t;
}

int32_t vertex_count_of(const std::vector<float>& xyz) {
  return static_cast<int32_t>(xyz.size() / 3);
}

MetricsResult compare(const Triangles& t, const std::vector<float>& pred, const std::vector<float>& truth,
                      uint32_t flags = 0, const BandSplitFn* split = nullptr) {
  MetricsOptions options;
  options.flags = flags;
  return compute_metrics(t, vertex_count_of(truth), pred.data(), 0, truth.data(), 0, 1, options, split);
}

std::vector<float> transformed(const std::vector<float>& xyz, const Eigen::Matrix3f& linear,
                               const Eigen::Vector3f& shift) {
  std::vector<float> out(xyz.size());
  for (size_t v = 0; v < xyz.size() / 3; ++v)
    Eigen::Vector3f::Map(&out[3 * v]) = linear * Eigen::Vector3f::Map(&xyz[3 * v]) + shift;
  return out;
}

using pleat_test::expect_error;

// A linear projection simple enough to check by hand: low = the mean of the
// frame's vectors (the constant component), mid = 0, high = the rest.
BandSplitFn mean_split(size_t vertex_count) {
  auto n = static_cast<Eigen::Index>(vertex_count);
  return [n](const float* in, size_t frames, float* low, float* mid, float* high) {
    for (size_t f = 0; f < frames; ++f) {
      size_t offset = 3 * static_cast<size_t>(n) * f;
      Eigen::Map<const Points3f> x(in + offset, n, 3);
      Eigen::RowVector3f mean = x.colwise().mean();
      Eigen::Map<Points3f>(low + offset, n, 3).rowwise() = mean;
      Eigen::Map<Points3f>(mid + offset, n, 3).setZero();
      Eigen::Map<Points3f>(high + offset, n, 3) = x.rowwise() - mean;
    }
  };
}

// ---- Whole-sequence entry point -----------------------------------------------

TEST(Metrics, IdenticalMeshesGiveExactlyZero) {
  pleat_test::SimpleMesh m = pleat_test::icosphere(2, 0.3f);
  BandSplitFn split = mean_split(m.vertex_count());
  MetricsResult r = compare(triangles_of(m), m.positions, m.positions, 0, &split);
  EXPECT_EQ(r.computed, kAllMetrics);
  EXPECT_EQ(r.frame_count, 1u);
  for (double e : {r.e_verts_cm, r.e_vnorm_deg, r.e_fnorm_deg, r.e_edge_percent, r.e_curv, r.e_low_cm,
                   r.e_mid_cm, r.e_high_cm, r.self_collision_percent})
    EXPECT_EQ(e, 0.0);
}

TEST(Metrics, TranslationMovesVerticesOnly) {
  pleat_test::SimpleMesh m = pleat_test::icosphere(2, 0.3f);
  BandSplitFn split = mean_split(m.vertex_count());
  Eigen::Vector3f shift(0.01f, 0.02f, -0.02f);  // 3 cm long
  std::vector<float> pred = transformed(m.positions, Eigen::Matrix3f::Identity(), shift);
  MetricsResult r = compare(triangles_of(m), pred, m.positions, 0, &split);
  EXPECT_NEAR(r.e_verts_cm, 3.0, 1e-5);
  EXPECT_NEAR(r.e_vnorm_deg, 0.0, 1e-3);
  EXPECT_NEAR(r.e_fnorm_deg, 0.0, 1e-3);
  EXPECT_NEAR(r.e_edge_percent, 0.0, 1e-3);
  EXPECT_NEAR(r.e_curv, 0.0, 1e-3 / (0.3 * 0.3));  // K itself is about 11 / m^2
  EXPECT_NEAR(r.e_low_cm, 3.0, 1e-5);              // a rigid shift is all low band
  EXPECT_NEAR(r.e_mid_cm, 0.0, 1e-12);
  EXPECT_NEAR(r.e_high_cm, 0.0, 1e-5);
}

TEST(Metrics, ScalingByTenPercentGivesTenPercentEdgeError) {
  pleat_test::SimpleMesh m = pleat_test::icosphere(1, 0.5f);
  std::vector<float> pred =
      transformed(m.positions, 1.1f * Eigen::Matrix3f::Identity(), Eigen::Vector3f::Zero());
  MetricsResult r = compare(triangles_of(m), pred, m.positions);
  EXPECT_NEAR(r.e_edge_percent, 10.0, 1e-4);
  EXPECT_NEAR(r.e_verts_cm, 5.0, 1e-4);  // every vertex moves 0.1 * 0.5 m outwards
  EXPECT_NEAR(r.e_fnorm_deg, 0.0, 1e-3);
  // K scales by 1 / 1.1^2.
  EXPECT_NEAR(r.e_curv, (1.0 - 1.0 / 1.21) * 4.0, 0.1 * 4.0);
}

TEST(Metrics, RotatedTriangleNormalsDifferByTheRotationAngle) {
  std::vector<float> truth = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  Eigen::Matrix3f rotation =
      Eigen::AngleAxisf(static_cast<float>(kPi / 6), Eigen::Vector3f::UnitX()).toRotationMatrix();
  std::vector<float> pred = transformed(truth, rotation, Eigen::Vector3f::Zero());
  Triangles t(1, 3);
  t << 0, 1, 2;
  MetricsResult r = compare(t, pred, truth);
  EXPECT_NEAR(r.e_fnorm_deg, 30.0, 1e-4);
  EXPECT_NEAR(r.e_vnorm_deg, 30.0, 1e-4);
  EXPECT_NEAR(r.e_edge_percent, 0.0, 1e-4);
  // Vertex 2 moves on a circle of radius 1 by 30 degrees: chord 2 sin(15 deg).
  EXPECT_NEAR(r.e_verts_cm, 100.0 * 2.0 * std::sin(kPi / 12) / 3.0, 1e-4);
}

TEST(Metrics, MeansOverFramesWithStrides) {
  pleat_test::SimpleMesh m = pleat_test::grid(4, 4, 0.1f);
  size_t n = m.positions.size(), stride = n + 5;
  std::vector<float> truth(2 * stride, 0.0f), pred(2 * stride, 0.0f);
  for (size_t f = 0; f < 2; ++f)
    for (size_t i = 0; i < n; ++i) truth[f * stride + i] = pred[f * stride + i] = m.positions[i];
  for (size_t i = 2; i < n; i += 3) pred[stride + i] += 0.04f;  // frame 1 lifted 4 cm
  MetricsOptions options;
  options.flags = PLEAT_METRIC_VERTEX | PLEAT_METRIC_SELF_COLLISION;
  MetricsResult r = compute_metrics(triangles_of(m), vertex_count_of(m.positions), pred.data(), stride,
                                    truth.data(), stride, 2, options, nullptr);
  EXPECT_EQ(r.computed, options.flags);
  EXPECT_EQ(r.frame_count, 2u);
  EXPECT_NEAR(r.e_verts_cm, 2.0, 1e-5);
  EXPECT_EQ(r.e_edge_percent, 0.0);  // not asked for
  EXPECT_EQ(r.self_collision_percent, 0.0);
}

TEST(Metrics, BandErrorsOfALocalBump) {
  pleat_test::SimpleMesh m = pleat_test::grid(5, 5, 0.1f);
  size_t n = m.vertex_count();
  BandSplitFn split = mean_split(n);
  std::vector<float> pred = m.positions;
  pred[2] += 0.25f;  // vertex 0 up by 25 cm
  MetricsResult r = compare(triangles_of(m), pred, m.positions, PLEAT_METRIC_BANDS, &split);
  EXPECT_EQ(r.computed, static_cast<uint32_t>(PLEAT_METRIC_BANDS));
  double d = 25.0, nn = static_cast<double>(n);
  EXPECT_NEAR(r.e_low_cm, d / nn, 1e-4);
  EXPECT_EQ(r.e_mid_cm, 0.0);
  EXPECT_NEAR(r.e_high_cm, (d * (1 - 1 / nn) + (nn - 1) * d / nn) / nn, 1e-4);
}

TEST(Metrics, SkipsBandsWithoutAProjectionUnlessAsked) {
  pleat_test::SimpleMesh m = pleat_test::grid(3, 3, 0.1f);
  MetricsResult r = compare(triangles_of(m), m.positions, m.positions);
  EXPECT_EQ(r.computed, kAllMetrics & ~PLEAT_METRIC_BANDS);
  expect_error([&] { compare(triangles_of(m), m.positions, m.positions, PLEAT_METRIC_BANDS); },
               PLEAT_ERROR_NOT_PREPARED, "band");
}

TEST(Metrics, RejectsBadInput) {
  pleat_test::SimpleMesh m = pleat_test::grid(3, 3, 0.1f);
  Triangles t = triangles_of(m);
  std::vector<float> pred = m.positions;
  pred[3 * 4 + 1] = std::nanf("");
  expect_error([&] { compare(t, pred, m.positions); }, PLEAT_ERROR_INVALID_ARGUMENT,
               "predicted frame 0 vertex 4");
  expect_error([&] { compare(t, m.positions, pred); }, PLEAT_ERROR_INVALID_ARGUMENT,
               "truth frame 0 vertex 4");
  Triangles bad = t;
  bad(3, 1) = 9;
  expect_error([&] { compare(bad, m.positions, m.positions); }, PLEAT_ERROR_INVALID_ARGUMENT,
               "triangle 3 corner 1: index 9");
  expect_error([&] { compare(t, m.positions, m.positions, 0x400); }, PLEAT_ERROR_INVALID_ARGUMENT, "flags");
  MetricsOptions options;
  expect_error(
      [&] { compute_metrics(t, 9, m.positions.data(), 0, m.positions.data(), 0, 0, options, nullptr); },
      PLEAT_ERROR_INVALID_ARGUMENT, "frame");
  expect_error(
      [&] { compute_metrics(t, 9, m.positions.data(), 26, m.positions.data(), 0, 1, options, nullptr); },
      PLEAT_ERROR_INVALID_ARGUMENT, "stride 26");
  options.collision_prefilter = -1;
  expect_error(
      [&] { compute_metrics(t, 9, m.positions.data(), 0, m.positions.data(), 0, 1, options, nullptr); },
      PLEAT_ERROR_INVALID_ARGUMENT, "collision_prefilter");
}

TEST(Metrics, DegenerateFacesAndIsolatedVerticesAreSkipped) {
  // Triangle 1 collapses to a line in the prediction; vertex 4 is isolated.
  std::vector<float> truth = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 5, 5, 5};
  std::vector<float> pred = truth;
  pred[9] = 0.5f, pred[10] = 0.5f;  // vertex 3 onto the diagonal 1-2
  Triangles t(2, 3);
  t << 0, 1, 2, 1, 3, 2;
  MetricsResult r = compare(t, pred, truth);
  EXPECT_EQ(r.e_fnorm_deg, 0.0);  // only face 0 counts, and it did not turn
  EXPECT_TRUE(std::isfinite(r.e_vnorm_deg));
  EXPECT_TRUE(std::isfinite(r.e_curv));
}

// ---- Gaussian curvature ----------------------------------------------------------

TEST(Curvature, IcosphereTotalIsFourPiAndKApproachesOneOverRSquared) {
  const double r = 2.0;
  double previous_error = INFINITY;
  for (int subdivisions = 2; subdivisions <= 4; ++subdivisions) {
    SCOPED_TRACE(subdivisions);
    pleat_test::SimpleMesh m = pleat_test::icosphere(subdivisions, static_cast<float>(r));
    Triangles t = triangles_of(m);
    Points3d x =
        Eigen::Map<const Points3f>(m.positions.data(), vertex_count_of(m.positions), 3).cast<double>();
    std::vector<uint8_t> interior = interior_vertex_mask(t, static_cast<int32_t>(x.rows()));
    EXPECT_EQ(std::count(interior.begin(), interior.end(), 1), x.rows());  // closed surface
    Eigen::VectorXd k = gaussian_curvature(x, t, interior);
    Eigen::VectorXd area = vertex_areas(x, t);
    EXPECT_NEAR(k.dot(area), 4.0 * kPi, 1e-9);  // Gauss-Bonnet: the defects sum to 4 pi
    Eigen::ArrayXd relative = (k.array() * r * r - 1.0).abs();
    // The mean error shrinks about fourfold per subdivision. The 12 valence-5
    // vertices of the icosahedron keep ~15 %: angle defect over barycentric
    // area does not converge pointwise at irregular vertices.
    EXPECT_LT(relative.mean(), previous_error / 3.5);
    EXPECT_LT(relative.maxCoeff(), 0.155);
    previous_error = relative.mean();
  }
  EXPECT_LT(previous_error, 0.002);
}

TEST(Curvature, HandComputedApexOfAFourSidedPyramid) {
  // Apex (0,0,1) over (+-1,0,0), (0,+-1,0): every apex angle is 60 degrees
  // (cos = 1/2), so the defect is 2 pi - 4 pi / 3 = 2 pi / 3; each face has area
  // sqrt(3) / 2, so the apex's third of the area is 2 sqrt(3) / 3 and
  // K = pi / sqrt(3). The flat fan (apex at z = 0) has K = 0.
  std::vector<float> truth = {0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0};
  std::vector<float> pred = truth;
  pred[2] = 1.0f;
  Triangles t(4, 3);
  t << 0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1;
  EXPECT_EQ(interior_vertex_mask(t, 5), (std::vector<uint8_t>{1, 0, 0, 0, 0}));
  MetricsResult r = compare(t, pred, truth, PLEAT_METRIC_CURVATURE);
  EXPECT_NEAR(r.e_curv, kPi / std::sqrt(3.0), 1e-6);
}

// ---- Self-collision --------------------------------------------------------------

// Triangle A lies in z = 0; triangle B in x = 0. B's edge 0-1 pierces A at
// (0, 0.5, 0) and A's edge along y = 0 pierces B at the origin: both faces hit.
const std::vector<float> kCrossing = {-1, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0.5f, 1, 0, 0.5f, -1, 0, -3, 0};

Triangles two_faces() {
  Triangles t(2, 3);
  t << 0, 1, 2, 3, 4, 5;
  return t;
}

TEST(SelfCollision, InterlockedTrianglesHitEachOther) {
  MetricsResult r = compare(two_faces(), kCrossing, kCrossing, PLEAT_METRIC_SELF_COLLISION);
  EXPECT_DOUBLE_EQ(r.self_collision_percent, 100.0);
}

TEST(SelfCollision, TriangleThroughAnotherHitsOnlyThatOne) {
  // B's two long edges pierce A's interior; no edge of A reaches B.
  std::vector<float> x = {-1, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0.4f, 1, 0, 0.6f, 1, 0, 0.5f, -1};
  MetricsResult r = compare(two_faces(), x, x, PLEAT_METRIC_SELF_COLLISION);
  EXPECT_DOUBLE_EQ(r.self_collision_percent, 50.0);
}

TEST(SelfCollision, ParallelTrianglesAndFlatGridsDoNotCollide) {
  std::vector<float> x = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.001f, 1, 0, 0.001f, 0, 1, 0.001f};
  EXPECT_EQ(compare(two_faces(), x, x, PLEAT_METRIC_SELF_COLLISION).self_collision_percent, 0.0);
  pleat_test::SimpleMesh grid = pleat_test::grid(30, 30, 0.01f);
  EXPECT_EQ(compare(triangles_of(grid), grid.positions, grid.positions, PLEAT_METRIC_SELF_COLLISION)
                .self_collision_percent,
            0.0);
}

TEST(SelfCollision, SegmentTest) {
  Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(segment_crosses_triangle({0.2, 0.2, -1}, {0.2, 0.2, 1}, a, b, c));
  EXPECT_TRUE(segment_crosses_triangle({0.2, 0.2, 0}, {0.2, 0.2, 1}, a, b, c));     // touches
  EXPECT_FALSE(segment_crosses_triangle({0.2, 0.2, 0.5}, {0.2, 0.2, 1}, a, b, c));  // short
  EXPECT_FALSE(segment_crosses_triangle({0.8, 0.8, -1}, {0.8, 0.8, 1}, a, b, c));   // outside
  EXPECT_FALSE(segment_crosses_triangle({-1, 0.2, 0}, {2, 0.2, 0}, a, b, c));       // coplanar
}

TEST(SelfCollision, EdgesSharingAVertexWithTheFaceDoNotCount) {
  // An edge touches each face around its end points at the shared corner,
  // which the segment test counts; the adjacency rule is what drops them.
  Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(segment_crosses_triangle(a, {0.3, 0.3, 1}, a, b, c));
  pleat_test::SimpleMesh grid = pleat_test::grid(3, 3, 1.0f);
  Triangles t = triangles_of(grid);
  Points3d x = Eigen::Map<const Points3f>(grid.positions.data(), 9, 3).cast<double>();
  x(4, 2) = 0.7;  // a tent: every face now meets its neighbours at an angle
  for (auto search : {CollisionSearch::box_tree, CollisionSearch::brute_force}) {
    std::vector<uint8_t> hit = self_intersected_faces(x, t, unique_edges(t), 0.015, search);
    EXPECT_EQ(std::count(hit.begin(), hit.end(), 1), 0);
  }
}

TEST(SelfCollision, BoxTreeFindsWhatBruteForceFinds) {
  // A sheet crumpled by random bumps larger than its spacing: many crossings.
  pleat_test::SimpleMesh grid = pleat_test::grid(25, 25, 0.01f);
  Triangles t = triangles_of(grid);
  Points3d x = Eigen::Map<const Points3f>(grid.positions.data(), 625, 3).cast<double>();
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.012);
  for (Eigen::Index v = 0; v < x.rows(); ++v)
    x.row(v) += Eigen::RowVector3d(noise(rng), noise(rng), noise(rng));
  std::vector<Edge> edges = unique_edges(t);
  std::vector<uint8_t> fast = self_intersected_faces(x, t, edges, 0.015);
  std::vector<uint8_t> slow = self_intersected_faces(x, t, edges, 0.015, CollisionSearch::brute_force);
  EXPECT_EQ(fast, slow);
  EXPECT_GT(std::count(fast.begin(), fast.end(), 1), 50);
  EXPECT_EQ(self_intersected_faces(x, t, edges, 0.0), fast);  // radius-independent
}

}  // namespace
}  // namespace pleat

// Body penetration: behind the nearest body vertex's normal counts as inside.
// Frame 0: one of two garment vertices below a floor of body vertices (50 %);
// frame 1: both above (0 %); the mean is 25 %.
TEST(BodyPenetration, CountsVerticesBehindTheNearestBodyNormal) {
  const float body[2][9] = {{0, 0, 0, 1, 0, 0, 0, 0, 1}, {0, 0, 0, 1, 0, 0, 0, 0, 1}};
  const float normals[2][9] = {{0, 1, 0, 0, 1, 0, 0, 1, 0}, {0, 1, 0, 0, 1, 0, 0, 1, 0}};
  const float garment[2][6] = {{0.9f, 0.05f, 0, 0.1f, -0.01f, 0.9f}, {0.9f, 0.05f, 0, 0.1f, 0.01f, 0.9f}};
  EXPECT_DOUBLE_EQ(pleat::body_penetration_percent(&garment[0][0], 2, &body[0][0], &normals[0][0], 3, 2),
                   25.0);
  EXPECT_DOUBLE_EQ(pleat::body_penetration_percent(&garment[1][0], 2, &body[1][0], &normals[1][0], 3, 1),
                   0.0);
  float bad[2][6] = {{0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, NAN, 0}};
  pleat_test::expect_error(
      [&] { pleat::body_penetration_percent(&bad[0][0], 2, &body[0][0], &normals[0][0], 3, 2); },
      PLEAT_ERROR_INVALID_ARGUMENT, "garment frame 1 vertex 1 is not finite");
}
