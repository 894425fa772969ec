// The offset filter x = (I + L)^{-1} d (runtime/offset_filter.h): a
// hand-computed triangle, a constant field kept, and the property it exists
// for: across edges much shorter than h the offsets become nearly equal,
// while across edges longer than h they keep most of their difference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "garment/garment.h"
#include "runtime/offset_filter.h"

using namespace pleat;
using runtime::OffsetFilter;

namespace {

Garment equilateral(double side) {
  Points3d v(3, 3);
  v << 0, 0, 0, side, 0, 0, side / 2, side * std::sqrt(3.0) / 2, 0;
  Triangles t(1, 3);
  t << 0, 1, 2;
  return build_garment(v, t, {}, "triangle");
}

// Columns at the given x, rows 2 cm apart, two triangles per cell.
Garment grid(const std::vector<double>& xs, int rows) {
  const int cols = static_cast<int>(xs.size());
  Points3d v(rows * cols, 3);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) v.row(r * cols + c) << xs[c], 0.02 * r, 0.0;
  Triangles t(2 * (rows - 1) * (cols - 1), 3);
  int k = 0;
  for (int r = 0; r + 1 < rows; ++r)
    for (int c = 0; c + 1 < cols; ++c) {
      const int a = r * cols + c;
      t.row(k++) << a, a + 1, a + cols;
      t.row(k++) << a + 1, a + cols + 1, a + cols;
    }
  return build_garment(v, t, {}, "grid");
}

}  // namespace

// I + w (3 I − 1 1ᵀ) on an equilateral triangle with w = (h / side)² = 1:
// e_0 = 1/3 (1, 1, 1) + (e_0 − 1/3 (1, 1, 1)); the constant part is kept and
// the zero-mean part divided by 1 + 3w = 4, so x = (1/2, 1/4, 1/4).
TEST(OffsetFilter, EquilateralTriangleMatchesTheHandComputedSolve) {
  const OffsetFilter filter(equilateral(0.05), 0.05);
  std::vector<float> d = {1, 0, 2, 0, 0, 0, 0, 0, 0};  // x: e_0; z: 2 e_0
  filter.apply(d.data(), 1);
  const std::vector<float> want = {0.5f, 0, 1.0f, 0.25f, 0, 0.5f, 0.25f, 0, 0.5f};
  for (size_t i = 0; i < d.size(); ++i) EXPECT_NEAR(d[i], want[i], 1e-6) << i;
}

TEST(OffsetFilter, ConstantFieldIsKeptInEveryFrame) {
  const Garment g = grid({0, 0.02, 0.04, 0.042, 0.044, 0.064}, 4);
  const OffsetFilter filter(g, 0.01);
  const int n = g.rest.vertex_count();
  std::vector<float> d(size_t(2) * n * 3);
  for (int f = 0; f < 2; ++f)
    for (int v = 0; v < n; ++v)
      for (int c = 0; c < 3; ++c) d[(size_t(f) * n + v) * 3 + c] = 0.1f * (c + 1) - 0.3f * f;
  const std::vector<float> before = d;
  filter.apply(d.data(), 2);
  for (size_t i = 0; i < d.size(); ++i) EXPECT_NEAR(d[i], before[i], 1e-6) << i;
}

// Columns 2 mm apart in the middle of a 2 cm grid, h = 1 cm: the 2 mm edges
// weigh 25, the 2 cm edges 0.25.
std::vector<double> columns_with_a_cluster() {
  std::vector<double> xs;
  for (int c = 0; c <= 4; ++c) xs.push_back(0.02 * c);
  for (int c = 1; c <= 3; ++c) xs.push_back(0.08 + 0.002 * c);
  for (int c = 1; c <= 5; ++c) xs.push_back(0.086 + 0.02 * c);
  return xs;
}

// Noise, the roughest field there is: across the 2 mm edges almost nothing
// of its differences is left (the cluster moves as one).
TEST(OffsetFilter, VerticesJoinedByShortEdgesGetNearlyOneOffset) {
  const Garment g = grid(columns_with_a_cluster(), 5);
  const OffsetFilter filter(g, 0.01);
  const int n = g.rest.vertex_count();
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  std::vector<float> d(size_t(n) * 3);
  for (float& x : d) x = noise(rng);
  std::vector<float> x = d;
  filter.apply(x.data(), 1);
  double before = 0, after = 0;
  for (const Edge& e : g.edges) {
    if ((g.rest.vertices.row(e.a) - g.rest.vertices.row(e.b)).norm() > 0.005) continue;
    for (int c = 0; c < 3; ++c) {
      before += std::pow(d[e.a * 3 + c] - d[e.b * 3 + c], 2);
      after += std::pow(x[e.a * 3 + c] - x[e.b * 3 + c], 2);
    }
  }
  const double kept = std::sqrt(after / before);
  std::printf("rms difference across 2 mm edges kept: %.3f\n", kept);
  EXPECT_LT(kept, 0.05);
}

// A wave of 16 cm along the garment: L sin(k x) = c (h k)² sin(k x) with
// c = 1 from the edges along x and 1/2 from the diagonals (weighted by
// (h / √2 a)²), so about 1 − 1/(1 + 1.5 (h k)²) = 19 % of it is lost at
// h = 1 cm; the grid's ends and the cluster add a little.
TEST(OffsetFilter, SmoothFieldsChangeLittle) {
  const Garment g = grid(columns_with_a_cluster(), 5);
  const OffsetFilter filter(g, 0.01);
  const int n = g.rest.vertex_count();
  const double k = 2 * M_PI / 0.16;
  std::vector<float> d(size_t(n) * 3);
  for (int v = 0; v < n; ++v) d[v * 3 + 1] = static_cast<float>(std::sin(k * g.rest.vertices(v, 0)));
  std::vector<float> x = d;
  filter.apply(x.data(), 1);
  double change = 0, field = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    change += std::pow(x[i] - d[i], 2);
    field += std::pow(d[i], 2);
  }
  const double lost = std::sqrt(change / field);
  std::printf("rms change of a 16 cm wave: %.3f of the wave\n", lost);
  EXPECT_GT(lost, 0.15);
  EXPECT_LT(lost, 0.25);
}
