// Band cuts: requested counts, gap moves, zero eigenvalues, option checks.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "core/topology.h"
#include "spectral/bands.h"
#include "spectral/spectral_test_graphs.h"

namespace {

using pleat::BandOptions;
using pleat::SolverKind;

pleat::Csr mirrored_graph() {
  auto panel = pleat_test::grid(14, 11, 0.1f, Eigen::Vector3f(0.3f, 0.0f, 0.0f));
  return spectral_test::graph_of(pleat_test::concat(panel, pleat_test::mirrored_x(panel)));
}

TEST(SpectralBands, CutInsideRepeatedPairMovesToGap) {
  const pleat::Csr graph = mirrored_graph();  // 308 vertices, every eigenvalue twice
  ASSERT_EQ(graph.vertex_count(), 308);
  for (auto solver : {SolverKind::dense, SolverKind::slicing, SolverKind::hybrid}) {
    BandOptions options;
    options.solver = solver;
    options.low_fraction = 11.0 / 308.0;  // odd counts split a pair
    options.mid_fraction = 61.0 / 308.0;
    const auto basis = pleat::compute_band_basis(graph, options);
    EXPECT_EQ(basis.low_requested, 11);
    EXPECT_EQ(basis.mid_requested, 61);
    // The requested cut would split an exactly repeated pair...
    EXPECT_NEAR(basis.eigenvalues[11], basis.eigenvalues[10], 1e-10);
    EXPECT_NEAR(basis.eigenvalues[60], basis.eigenvalues[61], 1e-10);
    // ...so it moves by one, to the nearest gap (ties go up).
    EXPECT_EQ(basis.low_count, 12);
    EXPECT_EQ(basis.mid_count, 62);
    EXPECT_GE(basis.low_gap, pleat::kMinGap);
    EXPECT_GE(basis.mid_gap, pleat::kMinGap);
    EXPECT_DOUBLE_EQ(basis.mid_gap, basis.eigenvalues[62] - basis.eigenvalues[61]);
    EXPECT_EQ(basis.eigenvalues.size(), 63);
    EXPECT_EQ(basis.vectors.cols(), 62);
  }
}

TEST(SpectralBands, EigenvaluesInRangeOneZeroPerComponent) {
  auto panel = pleat_test::grid(6, 5, 0.1f);
  const auto mesh = pleat_test::concat(panel, pleat_test::mirrored_x(panel));
  const pleat::Csr graph = spectral_test::graph_of(mesh, 3);  // 2 panels + 3 isolated
  std::vector<int32_t> labels;
  ASSERT_EQ(pleat::connected_components(graph, &labels), 5);
  BandOptions options;
  options.solver = SolverKind::dense;
  options.low_fraction = 1.0 / 63.0;  // asks for 1: the five zeros must stay low
  options.mid_fraction = 1.0;         // whole spectrum
  const auto basis = pleat::compute_band_basis(graph, options);
  ASSERT_EQ(basis.vertex_count, 63);
  EXPECT_EQ(basis.low_requested, 1);
  EXPECT_EQ(basis.low_count, 5);
  EXPECT_EQ(basis.mid_count, 63);
  EXPECT_EQ(basis.mid_gap, std::numeric_limits<double>::infinity());
  ASSERT_EQ(basis.eigenvalues.size(), 63);
  int zeros = 0;
  for (Eigen::Index i = 0; i < basis.eigenvalues.size(); ++i) {
    EXPECT_GE(basis.eigenvalues[i], -1e-12);
    EXPECT_LE(basis.eigenvalues[i], 2.0 + 1e-12);
    zeros += std::abs(basis.eigenvalues[i]) < 1e-10;
  }
  EXPECT_EQ(zeros, 5);
  EXPECT_GT(basis.eigenvalues[5], 1e-3);
}

TEST(SpectralBands, RequestedCountsAreCeilings) {
  const pleat::Csr graph = spectral_test::graph_of(pleat_test::grid(20, 15, 0.1f));  // N = 300
  BandOptions options;
  options.solver = SolverKind::dense;
  const auto basis = pleat::compute_band_basis(graph, options);
  EXPECT_EQ(basis.low_requested, 10);  // 300 / 30 exactly, despite 1/30 round-off
  EXPECT_EQ(basis.mid_requested, 60);
  EXPECT_EQ(basis.solver, SolverKind::dense);
  options.low_fraction = 0.0101;  // 3.03 -> 4
  EXPECT_EQ(pleat::compute_band_basis(graph, options).low_requested, 4);
}

TEST(SpectralBands, NearestGapCut) {
  Eigen::VectorXd values(8);
  values << 0.0, 0.1, 0.2, 0.2, 0.3, 0.3, 0.3, 0.5;
  EXPECT_EQ(pleat::nearest_gap_cut(values, 100, 2, 1, 1e-5), 2);
  EXPECT_EQ(pleat::nearest_gap_cut(values, 100, 3, 1, 1e-5), 4);  // tie: up
  EXPECT_EQ(pleat::nearest_gap_cut(values, 100, 5, 1, 1e-5), 4);
  EXPECT_EQ(pleat::nearest_gap_cut(values, 100, 1, 3, 1e-5), 4);  // min_cut respected
  EXPECT_EQ(pleat::nearest_gap_cut(values, 100, 7, 1, 1e-5), 7);
  EXPECT_EQ(pleat::nearest_gap_cut(values, 100, 6, 5, 1e-5), 7);   // 6 is no gap, 7 is
  EXPECT_EQ(pleat::nearest_gap_cut(values, 100, 8, 5, 1e-5), -1);  // 8 may be a gap: unknown
  EXPECT_EQ(pleat::nearest_gap_cut(values, 100, 9, 8, 1e-5), -1);  // needs lambda[9]
  EXPECT_EQ(pleat::nearest_gap_cut(values, 8, 8, 8, 1e-5), 8);     // all of the spectrum
}

void expect_invalid(const BandOptions& options, const std::string& field) {
  const pleat::Csr graph = spectral_test::graph_of(pleat_test::grid(4, 4, 0.1f));
  try {
    pleat::compute_band_basis(graph, options);
    ADD_FAILURE() << "no error for " << field;
  } catch (const pleat::Error& e) {
    EXPECT_EQ(e.status(), PLEAT_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(SpectralBands, BadOptionsNameTheField) {
  BandOptions o;
  o.low_fraction = 0.0;
  expect_invalid(o, "low_fraction");
  o = {};
  o.low_fraction = std::nan("");
  expect_invalid(o, "low_fraction");
  o = {};
  o.mid_fraction = 1.5;
  expect_invalid(o, "mid_fraction");
  o = {};
  o.low_fraction = 0.5;
  o.mid_fraction = 0.25;
  expect_invalid(o, "low_fraction");
  o = {};
  o.solver = static_cast<SolverKind>(7);
  expect_invalid(o, "solver");
  o = {};
  o.projection = static_cast<pleat::ProjectionForm>(2);
  expect_invalid(o, "projection");
}

TEST(SpectralBands, EmptyGraphIsRejected) {
  try {
    pleat::compute_band_basis(pleat::Csr{}, BandOptions{});
    ADD_FAILURE();
  } catch (const pleat::Error& e) {
    EXPECT_EQ(e.status(), PLEAT_ERROR_INVALID_ARGUMENT);
  }
}

}  // namespace
