// Every training loss on a case with a known value, and its gradient
// against central finite differences in double.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "core/error.h"
#include "core/geodesic.h"
#include "core/geometry.h"
#include "garment/garment.h"
#include "losses.h"
#include "metrics/curvature.h"
#include "physics_fit.h"
#include "spectral/band_split.h"
#include "spectral/bands.h"

using namespace pleat;
using namespace pleat::training;

namespace {

// side x side grid of spacing `spacing` on the plane z = 0 (or two such
// sheets `gap` apart along z), prepared: bands and 10 cm geodesic neighbourhoods.
Garment sheet(int side, double spacing, double gap = -1.0) {
  const int sheets = gap >= 0 ? 2 : 1;
  Points3d v(sheets * side * side, 3);
  Triangles t(sheets * 2 * (side - 1) * (side - 1), 3);
  int k = 0;
  for (int s = 0; s < sheets; ++s) {
    const int base = s * side * side;
    for (int r = 0; r < side; ++r)
      for (int c = 0; c < side; ++c) v.row(base + r * side + c) << spacing * c, spacing * r, s * gap;
    for (int r = 0; r + 1 < side; ++r)
      for (int c = 0; c + 1 < side; ++c) {
        const int a = base + r * side + c;
        t.row(k++) << a, a + 1, a + side;
        t.row(k++) << a + 1, a + side + 1, a + side;
      }
  }
  GarmentBuildOptions o;
  o.weld_tolerance = -1.0;  // the two sheets must stay apart
  Garment g = build_garment(v, t, o, "sheet");
  g.prepared.emplace();
  g.prepared->bands = compute_band_basis(g.graph, BandOptions{}).cast<float>();
  g.prepared->geodesic_radius = 0.10;
  g.prepared->geodesic = geodesic_neighbourhoods(g.rest.vertices, g.graph, 0.10);
  return g;
}

torch::Tensor positions(const Garment& g) {
  return torch::from_blob(const_cast<double*>(g.rest.vertices.data()), {1, g.rest.vertex_count(), 3},
                          torch::kFloat64)
      .clone();
}

torch::Tensor wobble(const torch::Tensor& x, double amount, uint64_t seed) {
  torch::manual_seed(seed);
  return x + amount * (torch::rand_like(x) - 0.5);
}

// Autograd gradient of f at x against central differences of f.
void expect_gradient(const std::function<torch::Tensor(const torch::Tensor&)>& f, torch::Tensor x,
                     const char* what, double tolerance = 1e-6) {
  x = x.clone().to(torch::kFloat64).requires_grad_(true);
  f(x).backward();
  const torch::Tensor analytic = x.grad().clone();
  torch::NoGradGuard no_grad;
  auto flat = x.view({-1});
  double largest = 0;
  for (int64_t i = 0; i < flat.numel(); ++i) {
    const double keep = flat[i].item<double>(), h = 1e-6;
    flat[i] = keep + h;
    const double up = f(x).item<double>();
    flat[i] = keep - h;
    const double down = f(x).item<double>();
    flat[i] = keep;
    const double numeric = (up - down) / (2 * h);
    largest = std::max(largest, std::abs(numeric));
    ASSERT_NEAR(analytic.view({-1})[i].item<double>(), numeric, tolerance * (1 + std::abs(numeric)))
        << what << " entry " << i;
  }
  EXPECT_GT(largest, 1e-4) << what << ": the gradient check is not vacuous";
}

}  // namespace

TEST(TrainingLosses, FrequencyVertexLossSplitsLikeTheLibraryAndKeepsShiftsLow) {
  const Garment g = sheet(5, 0.05);
  const BandProjector bands(g.prepared->bands);
  const torch::Tensor truth = positions(g);
  // A rigid shift is all low band (random-walk projection): L_lv = |c|.
  const torch::Tensor shifted = truth + torch::tensor({0.03, -0.04, 0.0}, torch::kFloat64);
  const VertexLoss shift = frequency_vertex_loss(bands, shifted, truth, 2.0, 1.5);
  EXPECT_NEAR(shift.low.item<double>(), 0.05, 1e-6);
  EXPECT_NEAR(shift.mid.item<double>(), 0.0, 1e-6);
  EXPECT_NEAR(shift.high.item<double>(), 0.0, 1e-6);
  EXPECT_NEAR(shift.total.item<double>(), 0.05, 1e-6);
  // A random error: each band's term is the mean norm of split_bands' band.
  const torch::Tensor x = wobble(truth, 0.02, 1);
  const VertexLoss l = frequency_vertex_loss(bands, x, truth, 2.0, 1.5);
  const int n = g.rest.vertex_count();
  const torch::Tensor e = (x - truth).to(torch::kFloat32).contiguous();
  std::vector<float> low(n * 3), mid(n * 3), high(n * 3);
  split_bands(g.prepared->bands, e.data_ptr<float>(), 1, n * 3, low.data(), n * 3, mid.data(), n * 3,
              high.data(), n * 3);
  const auto mean_norm = [&](const std::vector<float>& b) {
    double s = 0;
    for (int i = 0; i < n; ++i)
      s += std::sqrt(b[i * 3] * b[i * 3] + b[i * 3 + 1] * b[i * 3 + 1] + b[i * 3 + 2] * b[i * 3 + 2]);
    return s / n;
  };
  EXPECT_NEAR(l.low.item<double>(), mean_norm(low), 1e-6);
  EXPECT_NEAR(l.mid.item<double>(), mean_norm(mid), 1e-6);
  EXPECT_NEAR(l.high.item<double>(), mean_norm(high), 1e-6);
  EXPECT_NEAR(l.total.item<double>(), mean_norm(low) + 2 * mean_norm(mid) + 1.5 * mean_norm(high), 1e-5);
  EXPECT_GT(l.high.item<double>(), 0.0);
  expect_gradient(
      [&](const torch::Tensor& p) { return frequency_vertex_loss(bands, p, truth, 2.0, 1.5).total; }, x,
      "vertex loss");
  EXPECT_NEAR(vertex_loss(shifted, truth).item<double>(), 0.05, 1e-12);
}

TEST(TrainingLosses, EdgeAndNormalLosses) {
  const Garment g = sheet(4, 0.1);
  const GarmentGeometry geometry(g);
  const torch::Tensor truth = positions(g);
  // Scaling by 1.1 stretches every edge by 10 %, whatever its length; so
  // does scaling by 0.9 the other way.
  EXPECT_NEAR(edge_loss(geometry, truth * 1.1, truth).item<double>(), 0.1, 1e-6);
  EXPECT_NEAR(edge_loss(geometry, truth * 0.9, truth).item<double>(), 0.1, 1e-6);
  // Stretching only along x: horizontal edges by 20 %, vertical ones not at
  // all, diagonals by the hand-computed sqrt(1.2^2 + 1) / sqrt(2) - 1.
  const torch::Tensor stretched = truth * torch::tensor({1.2, 1.0, 1.0}, truth.options());
  const torch::Tensor d = (truth[0].index_select(0, geometry.edges.select(1, 0)) -
                           truth[0].index_select(0, geometry.edges.select(1, 1)))
                              .abs();
  const torch::Tensor horizontal = (d.select(1, 0) > 1e-9) & (d.select(1, 1) < 1e-9),
                      vertical = (d.select(1, 0) < 1e-9) & (d.select(1, 1) > 1e-9);
  const double edges = double(geometry.edges.size(0)), h = horizontal.sum().item<double>(),
               v = vertical.sum().item<double>();
  const double expected =
      (0.2 * h + (std::sqrt(1.44 + 1.0) / std::sqrt(2.0) - 1.0) * (edges - h - v)) / edges;
  EXPECT_NEAR(edge_loss(geometry, stretched, truth).item<double>(), expected, 1e-6);
  // A quarter turn about x: every face normal turns by 90 degrees.
  const torch::Tensor turned = torch::stack({truth.select(2, 0), -truth.select(2, 2), truth.select(2, 1)}, 2);
  EXPECT_NEAR(normal_loss(geometry, turned, truth).item<double>(), 1.0, 1e-9);
  EXPECT_NEAR(normal_loss(geometry, truth, truth).item<double>(), 0.0, 1e-12);
  const torch::Tensor x = wobble(truth, 0.03, 2);
  expect_gradient([&](const torch::Tensor& p) { return edge_loss(geometry, p, truth); }, x, "edge loss");
  expect_gradient([&](const torch::Tensor& p) { return normal_loss(geometry, p, truth); }, x, "normal loss");
}

TEST(TrainingLosses, CurvatureLossComparesAngleSumsAtInteriorVertices) {
  // 3 x 3 sheet: only the centre has a closed fan. Lifting it by one
  // spacing, its six corners are two of 60 degrees (between axis
  // neighbours) and four of acos(sqrt(2/3)) (axis to diagonal neighbour),
  // against 2 pi flat. Its six triangles of s^2 / 2 give it a rest area of
  // s^2, so the defect counts kCurvatureReferenceArea / s^2 times.
  const double s = 0.1;
  const Garment small = sheet(3, s);
  const GarmentGeometry g3(small);
  ASSERT_EQ(g3.interior.size(0), 1);
  EXPECT_EQ(g3.interior[0].item<int64_t>(), 4);
  const torch::Tensor flat = positions(small);
  torch::Tensor lifted = flat.clone();
  lifted[0][4][2] = s;
  const double defect = 4 * M_PI / 3 - 4 * std::acos(std::sqrt(2.0 / 3.0));
  const double weight = kCurvatureReferenceArea / (s * s);
  const double tolerance = 1e-7 * weight * defect;  // the weight is stored as float32
  EXPECT_NEAR(curvature_loss(g3, lifted, flat).item<double>(), weight * defect, tolerance);
  EXPECT_NEAR(curvature_loss(g3, flat, lifted).item<double>(), weight * defect, tolerance);

  // A larger wobbled sheet against the metric's own angle sums (Eigen,
  // another implementation), and blind to rotation and uniform scale.
  const Garment g = sheet(5, s);
  const GarmentGeometry geometry(g);
  const torch::Tensor truth = wobble(positions(g), 0.03, 3), x = wobble(positions(g), 0.03, 4);
  const auto points = [](const torch::Tensor& p) {
    const torch::Tensor c = p[0].contiguous();
    return Points3d(Eigen::Map<const Points3d>(c.data_ptr<double>(), c.size(0), 3));
  };
  const Eigen::VectorXd sx = angle_sums(points(x), g.rest.triangles),
                        st = angle_sums(points(truth), g.rest.triangles);
  const std::vector<uint8_t> interior = interior_vertex_mask(g.rest.triangles, g.rest.vertex_count());
  const Eigen::VectorXd sheet_area = vertex_areas(g.rest.vertices, g.rest.triangles);
  double sum = 0;
  int count = 0;
  for (int v = 0; v < g.rest.vertex_count(); ++v)
    if (interior[v]) sum += std::abs(sx[v] - st[v]) * kCurvatureReferenceArea / sheet_area[v], ++count;
  EXPECT_EQ(count, 9);
  EXPECT_NEAR(curvature_loss(geometry, x, truth).item<double>(), sum / count, 1e-9);
  const torch::Tensor turned = torch::stack({truth.select(2, 0), -truth.select(2, 2), truth.select(2, 1)}, 2);
  EXPECT_NEAR(curvature_loss(geometry, 1.7 * turned + 0.3, truth).item<double>(), 0.0, 1e-9);
  expect_gradient([&](const torch::Tensor& p) { return curvature_loss(geometry, p, truth); }, x,
                  "curvature loss");

  // Columns 0.1, 0.02, 0.02 and 0.16 apart: the interior columns' rest
  // areas go as 0.12 : 0.04 : 0.18, and each |ΔΣθ| counts in proportion to
  // 1 / its area (the metric library's vertex areas), as in E_curv.
  Points3d v = g.rest.vertices;
  const double column_x[5] = {0.0, 0.1, 0.12, 0.14, 0.30};
  for (int i = 0; i < v.rows(); ++i) v(i, 0) = column_x[static_cast<int>(std::lround(v(i, 0) / s))];
  GarmentBuildOptions o;
  o.weld_tolerance = -1.0;
  const Garment squeezed = build_garment(v, g.rest.triangles, o, "squeezed");
  const GarmentGeometry uneven(squeezed);
  const Eigen::VectorXd area = vertex_areas(v, squeezed.rest.triangles);
  double interior_count = 0, weighted = 0;
  for (int i = 0; i < v.rows(); ++i)
    if (interior[i])
      interior_count += 1, weighted += std::abs(sx[i] - st[i]) * kCurvatureReferenceArea / area[i];
  EXPECT_NEAR(curvature_loss(uneven, x, truth).item<double>(), weighted / interior_count, 1e-7);
  EXPECT_NEAR(uneven.curvature_weight.max().item<double>() / uneven.curvature_weight.min().item<double>(),
              0.18 / 0.04, 1e-4);
}

TEST(TrainingLosses, SkinningSmoothnessPenalisesJumpsOfTheCorrectionToThePrior) {
  // 3 x 3 sheet, two joints; the prior moves weight from joint 0 to joint 1
  // across the columns: p = (1 - c/2, c/2) in column c.
  const Garment g = sheet(3, 0.1);
  const GarmentGeometry geometry(g);
  const torch::Tensor column = (positions(g)[0].select(1, 0) / 0.1).round();  // N
  const torch::Tensor prior = torch::stack({1 - column / 2, column / 2}, 1);  // N x 2
  ASSERT_EQ(geometry.edges.size(0), 16) << "6 horizontal, 6 vertical, 4 diagonal edges";

  // A correction that is the same everywhere costs nothing, whatever its size.
  const torch::Tensor shifted = (prior + torch::tensor({0.3, -0.3}, prior.options())).unsqueeze(0);
  EXPECT_NEAR(skinning_smoothness_loss(geometry, shifted, prior).item<double>(), 0.0, 1e-12);

  // (0.2, -0.2) added in column 2 only: the 3 horizontal and 2 diagonal edges
  // between columns 1 and 2 jump by |0.2| + |-0.2| each, so 5 x 0.4 / 16 in
  // that frame; a second, uncorrected frame halves the mean.
  const torch::Tensor step =
      (column == 2).to(prior.scalar_type()).unsqueeze(1) * torch::tensor({0.2, -0.2}, prior.options());
  const torch::Tensor frames = torch::stack({prior + step, prior});
  EXPECT_NEAR(skinning_smoothness_loss(geometry, frames, prior).item<double>(), 5 * 0.4 / 16 / 2, 1e-12);

  // Without a prior the weights themselves are compared: the prior's own
  // field changes by 0.5 + 0.5 along the 6 horizontal and 4 diagonal edges.
  EXPECT_NEAR(skinning_smoothness_loss(geometry, prior.unsqueeze(0), torch::Tensor()).item<double>(),
              10 * 1.0 / 16, 1e-12);

  expect_gradient([&](const torch::Tensor& w) { return skinning_smoothness_loss(geometry, w, prior); },
                  wobble(frames, 0.05, 3), "skinning smoothness");
}

TEST(TrainingLosses, OffsetSmoothnessIsTheOffsetSlopeAlongEachEdge) {
  // 3 x 3 sheet of spacing 0.1: 6 horizontal and 6 vertical edges of 0.1, and
  // 4 diagonals of 0.1 sqrt(2) that also advance 0.1 in x.
  const Garment g = sheet(3, 0.1);
  const GarmentGeometry geometry(g);
  const torch::Tensor x = positions(g)[0].select(1, 0);  // N
  const torch::Tensor zero = torch::zeros_like(x);

  // A uniform offset has no slope, whatever its size.
  const torch::Tensor shift = torch::stack({zero + 0.3, zero - 0.2, zero + 0.1}, 1).unsqueeze(0);
  EXPECT_NEAR(offset_smoothness_loss(geometry, shift).item<double>(), 0.0, 1e-12);

  // Offsets 0.05 x along z, in one frame of two: slope 0.05 on the horizontal
  // edges, 0 on the vertical ones, 0.05 / sqrt(2) on the diagonals.
  const torch::Tensor ramp = torch::stack({zero, zero, 0.05 * x}, 1);
  const torch::Tensor frames = torch::stack({ramp, torch::zeros_like(ramp)});
  EXPECT_NEAR(offset_smoothness_loss(geometry, frames).item<double>(),
              (6 * 0.05 + 4 * 0.05 / std::sqrt(2.0)) / 16 / 2, 1e-7);

  // The same jump costs ten times more across an edge ten times shorter.
  Points3d v = g.rest.vertices;
  for (int i = 0; i < v.rows(); ++i) v(i, 1) *= 0.1;  // rows 1 cm apart
  GarmentBuildOptions o;
  o.weld_tolerance = -1.0;
  const GarmentGeometry flat(build_garment(v, g.rest.triangles, o, "flat"));
  const torch::Tensor row = (positions(g)[0].select(1, 1) / 0.1).round();  // 0, 1, 2
  const torch::Tensor step = torch::stack({zero, zero, 0.001 * row}, 1).unsqueeze(0);
  const double diagonal = std::sqrt(0.1 * 0.1 + 0.01 * 0.01);
  EXPECT_NEAR(offset_smoothness_loss(geometry, step).item<double>(),
              (6 * 0.01 + 4 * 0.001 / std::sqrt(0.02)) / 16, 1e-7);
  EXPECT_NEAR(offset_smoothness_loss(flat, step).item<double>(), (6 * 0.1 + 4 * 0.001 / diagonal) / 16, 1e-6);

  expect_gradient([&](const torch::Tensor& b) { return offset_smoothness_loss(geometry, b); },
                  wobble(frames, 0.05, 4), "offset smoothness");
}

TEST(TrainingLosses, CollisionPenalisesVerticesBelowTheMarginAlongTheBodyNormal) {
  // Body: a coarse plane y = 0 facing +y; garment 1 cm below it, so
  // d = -1 cm and every vertex costs (0.4 + 1)³.
  const torch::Tensor body =
      torch::tensor({-1.0, 0.0, -1.0, 1.0, 0.0, -1.0, -1.0, 0.0, 1.0, 1.0, 0.0, 1.0}, torch::kFloat64)
          .view({1, 4, 3});
  const torch::Tensor normals = torch::tensor({0.0, 1.0, 0.0}, torch::kFloat64).expand({1, 4, 3});
  torch::Tensor x = torch::tensor({0.1, -0.01, 0.2, -0.3, -0.01, 0.5}, torch::kFloat64).view({1, 2, 3});
  EXPECT_NEAR(collision_loss(x, body, normals).item<double>(), std::pow(1.4, 3), 1e-9);
  EXPECT_NEAR(
      collision_loss(x + torch::tensor({0.0, 0.02, 0.0}, torch::kFloat64), body, normals).item<double>(), 0.0,
      1e-12)
      << "1 cm above the body, outside the 0.4 cm margin";
  expect_gradient([&](const torch::Tensor& p) { return collision_loss(p, body, normals); }, x,
                  "collision loss");
}

TEST(TrainingLosses, SelfCollisionRepelsGeodesicallyFarVerticesThatCameClose) {
  // Two sheets 1 cm apart, 3 cm spacing: each vertex has exactly one
  // partner within 2 cm, on the other sheet, geodesically unreachable.
  const Garment g = sheet(3, 0.03, 0.01);
  const GarmentGeometry geometry(g);
  const torch::Tensor x = positions(g);
  EXPECT_NEAR(self_collision_loss(geometry, x).item<double>(), std::exp(-8.0), 1e-12);
  // One sheet alone: neighbours are 3 cm apart, nothing is close.
  const Garment one = sheet(3, 0.03);
  EXPECT_EQ(self_collision_loss(GarmentGeometry(one), positions(one)).item<double>(), 0.0);
  // A dense sheet: its vertices 1.5 cm apart are close, but they are
  // geodesic neighbours (within 10 cm along the surface): no collision.
  const Garment dense = sheet(5, 0.015);
  EXPECT_EQ(self_collision_loss(GarmentGeometry(dense), positions(dense)).item<double>(), 0.0);
  expect_gradient([&](const torch::Tensor& p) { return self_collision_loss(geometry, p); },
                  wobble(x, 0.004, 3), "self-collision loss");
}

TEST(TrainingLosses, GravityStretchShearAndBending) {
  const Garment g = sheet(4, 0.1);
  const GarmentGeometry geometry(g);
  const torch::Tensor rest = positions(g);
  const double area = geometry.rest_areas.sum().item<double>();
  EXPECT_NEAR(area, 0.09, 1e-7);  // float32 rest data
  // Lifting by 2 cm stores m g h.
  EXPECT_NEAR(gravity_loss(geometry, rest + torch::tensor({0.0, 0.02, 0.0}, torch::kFloat64)).item<double>(),
              0.15 * area * 9.81 * 0.02, 1e-8);
  // Uniform scaling by 1.1: both directions stretch by 10 %, no shear.
  EXPECT_NEAR(stretch_loss(geometry, rest * 1.1).item<double>(), 2 * 0.01 * area, 1e-8);
  EXPECT_NEAR(shear_loss(geometry, rest * 1.1).item<double>(), 0.0, 1e-12);
  // Shear x += 0.2 y: w_u . w_v = ±0.2 in every face.
  const torch::Tensor sheared =
      rest + torch::stack({0.2 * rest.select(2, 1), torch::zeros_like(rest.select(2, 0)),
                           torch::zeros_like(rest.select(2, 0))},
                          2);
  EXPECT_NEAR(shear_loss(geometry, sheared).item<double>(), 0.04 * area, 1e-8);
  EXPECT_NEAR(bending_loss(geometry, rest).item<double>(), 0.0, 1e-12);
  // One hinge: two right triangles folded by 0.5 rad about their shared edge.
  Points3d v(4, 3);
  v << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0;
  Triangles t(2, 3);
  t << 0, 1, 2, 1, 0, 3;
  const GarmentGeometry hinge(build_garment(v, t, {}, "hinge"));
  ASSERT_EQ(hinge.hinges.size(0), 1);
  const torch::Tensor folded =
      torch::tensor({0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.5, -std::cos(0.5), std::sin(0.5)},
                    torch::kFloat64)
          .view({1, 4, 3});
  EXPECT_NEAR(bending_loss(hinge, folded).item<double>(), 3.0 * 0.25, 1e-6) << "w = 3 |e|² / (A1 + A2) = 3";
  const torch::Tensor x = wobble(rest, 0.03, 4);
  expect_gradient([&](const torch::Tensor& p) { return gravity_loss(geometry, p); }, x, "gravity loss");
  expect_gradient([&](const torch::Tensor& p) { return stretch_loss(geometry, p); }, x, "stretch loss");
  expect_gradient([&](const torch::Tensor& p) { return shear_loss(geometry, p); }, x, "shear loss");
  expect_gradient([&](const torch::Tensor& p) { return bending_loss(geometry, p); }, x, "bending loss");
}

TEST(TrainingLosses, InertiaIsTheImplicitEulerStep) {
  const Garment g = sheet(4, 0.1);
  const GarmentGeometry geometry(g);
  const torch::Tensor rest = positions(g);
  const double mass = 0.15 * geometry.rest_areas.sum().item<double>(), fps = 30.0, h = 1.0 / fps;
  const torch::Tensor step = torch::tensor({0.01, -0.02, 0.005}, torch::kFloat64);
  // Constant velocity: nothing to resist.
  EXPECT_NEAR(inertia_loss(geometry, rest + 2 * step, rest + step, rest, fps).item<double>(), 0.0, 1e-12);
  // A uniform acceleration a: x - 2p + q = a h², so the loss is M |a|² h² / 2.
  const torch::Tensor a = torch::tensor({0.0, 3.0, 4.0}, torch::kFloat64);  // |a| = 5 m/s²
  EXPECT_NEAR(inertia_loss(geometry, rest + a * h * h, rest, rest, fps).item<double>(),
              mass * 25.0 * h * h / 2, 1e-9);
  // With gravity, the minimum is a free fall: x = 2p - q - g h² ŷ.
  const torch::Tensor fallen =
      (rest + 2 * step + torch::tensor({0.0, -9.81 * h * h, 0.0}, torch::kFloat64)).set_requires_grad(true);
  const torch::Tensor potential =
      inertia_loss(geometry, fallen, rest + step, rest, fps) + gravity_loss(geometry, fallen);
  potential.backward();
  EXPECT_LT(fallen.grad().abs().max().item<double>(), 1e-9);
  expect_gradient([&](const torch::Tensor& p) { return inertia_loss(geometry, p, rest + step, rest, fps); },
                  wobble(rest, 0.03, 4), "inertia loss");
}

// Frames stepped by this very incremental potential (each frame its minimum,
// found by L-BFGS): the fit must find the weights they were made with.
TEST(PhysicsFit, RecoversTheWeightsOfItsOwnSimulation) {
  const Garment g = sheet(4, 0.1);
  const GarmentGeometry geometry(g);
  const double fps = 30.0, k_stretch = 2.0, k_shear = 1.0, k_bending = 0.002;
  std::vector<torch::Tensor> frames = {wobble(positions(g), 0.02, 5)};
  torch::manual_seed(6);
  frames.push_back(frames[0] + 0.01 * (torch::rand_like(frames[0]) - 0.5));
  for (int t = 2; t < 14; ++t) {
    const torch::Tensor previous = frames[t - 1], before = frames[t - 2];
    torch::Tensor x = (2 * previous - before).clone().set_requires_grad(true);
    torch::optim::LBFGS solver({x}, torch::optim::LBFGSOptions(1.0)
                                        .max_iter(2000)
                                        .tolerance_grad(1e-13)
                                        .tolerance_change(1e-18)
                                        .line_search_fn("strong_wolfe"));
    const auto potential = [&] {
      solver.zero_grad();
      const torch::Tensor e = inertia_loss(geometry, x, previous, before, fps) + gravity_loss(geometry, x) +
                              k_stretch * stretch_loss(geometry, x) + k_shear * shear_loss(geometry, x) +
                              k_bending * bending_loss(geometry, x);
      e.backward();
      return e;
    };
    solver.step(potential);
    frames.push_back(x.detach());
  }
  PhysicsFitter fitter;
  fitter.add(geometry, torch::cat(frames), torch::zeros({14, 0, 3}, torch::kFloat64), fps);
  const PhysicsFit fit = fitter.solve();
  EXPECT_EQ(fit.frames, 12);
  EXPECT_EQ(fit.rows, 12 * 16 * 3);
  EXPECT_NEAR(fit.weights.at("gravity"), 1.0, 1e-4);
  EXPECT_NEAR(fit.weights.at("stretch"), k_stretch, 1e-4 * k_stretch);
  EXPECT_NEAR(fit.weights.at("shear"), k_shear, 1e-4 * k_shear);
  EXPECT_NEAR(fit.weights.at("bending"), k_bending, 1e-3 * k_bending);
  EXPECT_NEAR(fit.elastic_weights.at("stretch"), k_stretch, 1e-4 * k_stretch);
  EXPECT_LT(fit.residual, 1e-4);
  EXPECT_GT(fit.gravity_only_residual, 0.01);  // the elastic forces are a real part of the motion
  // Nothing added: a clear error, not a division by zero.
  EXPECT_THROW(PhysicsFitter().solve(), Error);
}
