// The three eigensolvers agree on band bases (eigenvalues, cuts, projections)
// on meshes chosen for their spectra: plain, repeated, isolated, symmetric.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "spectral/band_split.h"
#include "spectral/bands.h"
#include "spectral/eigen_pairs.h"
#include "spectral/eigensolver.h"
#include "spectral/laplacian.h"
#include "spectral/slicing_solver.h"
#include "spectral/spectral_test_graphs.h"

namespace {

using pleat::BandBasis;
using pleat::SolverKind;

struct Case {
  std::string name;
  pleat::Csr graph;
  pleat::Points3d positions;
};

Case plain_grid() {
  auto m = pleat_test::grid(24, 18, 0.1f);
  return {"grid", spectral_test::graph_of(m), spectral_test::positions_of(m)};
}

Case mirrored_panels() {
  auto panel = pleat_test::grid(14, 11, 0.1f, Eigen::Vector3f(0.3f, 0.0f, 0.0f));
  auto m = pleat_test::concat(panel, pleat_test::mirrored_x(panel));
  return {"mirrored", spectral_test::graph_of(m), spectral_test::positions_of(m)};
}

Case with_isolated() {
  auto m = pleat_test::grid(17, 15, 0.1f);
  return {"isolated", spectral_test::graph_of(m, 5), spectral_test::positions_of(m, 5)};
}

Case sphere() {
  auto m = pleat_test::icosphere(3, 1.0f);  // 642 vertices, icosahedral multiplicities
  return {"sphere", spectral_test::graph_of(m), spectral_test::positions_of(m)};
}

// Low and mid band of X (symmetric and random-walk, whichever the basis has).
void bands(const BandBasis<double>& b, const pleat::Points3d& x, pleat::Points3d* low, pleat::Points3d* mid) {
  low->resize(x.rows(), 3);
  mid->resize(x.rows(), 3);
  pleat::split_bands<double>(b, x.data(), 1, 0, low->data(), 0, mid->data(), 0, nullptr, 0);
}

BandBasis<double> solve(const Case& c, SolverKind kind, pleat::ProjectionForm form) {
  pleat::BandOptions options;
  options.solver = kind;
  options.projection = form;
  const auto start = std::chrono::steady_clock::now();
  BandBasis<double> b = pleat::compute_band_basis(c.graph, options);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::printf("%-9s solver %u: N %d low %d/%d mid %d/%d gaps %.3g %.3g  %.0f ms\n", c.name.c_str(),
              static_cast<unsigned>(kind), b.vertex_count, b.low_count, b.low_requested, b.mid_count,
              b.mid_requested, b.low_gap, b.mid_gap, ms);
  return b;
}

void expect_agree(const Case& c) {
  for (auto form : {pleat::ProjectionForm::random_walk, pleat::ProjectionForm::symmetric}) {
    const BandBasis<double> dense = solve(c, SolverKind::dense, form);
    EXPECT_EQ(dense.solver, SolverKind::dense);
    pleat::Points3d dense_low, dense_mid;
    bands(dense, c.positions, &dense_low, &dense_mid);
    for (auto kind : {SolverKind::slicing, SolverKind::hybrid}) {
      const BandBasis<double> other = solve(c, kind, form);
      SCOPED_TRACE(c.name + " solver " + std::to_string(static_cast<int>(kind)));
      EXPECT_EQ(other.solver, kind);
      ASSERT_EQ(other.low_count, dense.low_count);
      ASSERT_EQ(other.mid_count, dense.mid_count);
      ASSERT_EQ(other.eigenvalues.size(), dense.eigenvalues.size());
      EXPECT_LT((other.eigenvalues - dense.eigenvalues).cwiseAbs().maxCoeff(), 1e-10);
      EXPECT_NEAR(other.low_gap, dense.low_gap, 1e-10);
      EXPECT_NEAR(other.mid_gap, dense.mid_gap, 1e-10);
      // Orthonormal basis.
      const Eigen::MatrixXd gram = other.vectors.transpose() * other.vectors;
      EXPECT_LT((gram - Eigen::MatrixXd::Identity(gram.rows(), gram.cols())).norm(), 1e-9);
      pleat::Points3d low, mid;
      bands(other, c.positions, &low, &mid);
      const double scale = c.positions.norm();
      EXPECT_LT((low - dense_low).norm() / scale, 1e-6);
      EXPECT_LT((mid - dense_mid).norm() / scale, 1e-6);
    }
  }
}

TEST(SpectralSolvers, AgreeOnGrid) {
  expect_agree(plain_grid());
}
TEST(SpectralSolvers, AgreeOnMirroredPanels) {
  expect_agree(mirrored_panels());
}
TEST(SpectralSolvers, AgreeWithIsolatedVertices) {
  expect_agree(with_isolated());
}
TEST(SpectralSolvers, AgreeOnSphere) {
  expect_agree(sphere());
}

TEST(SpectralSolvers, ResidualsAreTight) {
  const Case c = sphere();
  const auto laplacian = pleat::normalized_laplacian(c.graph);
  for (auto kind : {SolverKind::dense, SolverKind::slicing, SolverKind::hybrid}) {
    const pleat::EigenPairs pairs = pleat::solve_lowest(laplacian, 140, kind);
    EXPECT_LT(pleat::max_residual(laplacian, pairs), pleat::kResidualTolerance) << static_cast<int>(kind);
  }
}

TEST(SpectralSolvers, SlicingIsIdenticalForAnyWorkerCount) {
  // Several slices (and mirrored, repeated eigenvalues) so that workers
  // really interleave; the result must match bit for bit.
  const Case c = mirrored_panels();
  const auto laplacian = pleat::normalized_laplacian(c.graph);
  const int count = 5 * pleat::kSliceSize;
  const pleat::EigenPairs one = pleat::solve_slicing(laplacian, count, 1);
  EXPECT_LT(pleat::max_residual(laplacian, one), pleat::kResidualTolerance);
  for (int workers : {2, 3}) {
    const pleat::EigenPairs many = pleat::solve_slicing(laplacian, count, workers);
    SCOPED_TRACE(workers);
    ASSERT_EQ(many.values.size(), count);
    EXPECT_TRUE(many.values == one.values);
    EXPECT_TRUE(many.vectors == one.vectors);
  }
}

TEST(SpectralSolvers, AutomaticPicksDenseForSmallMeshes) {
  EXPECT_EQ(pleat::resolve_solver(SolverKind::automatic, pleat::kDenseSolverLimit - 1), SolverKind::dense);
  EXPECT_EQ(pleat::resolve_solver(SolverKind::automatic, pleat::kDenseSolverLimit), SolverKind::slicing);
  EXPECT_EQ(pleat::resolve_solver(SolverKind::hybrid, 10), SolverKind::hybrid);
}

}  // namespace
