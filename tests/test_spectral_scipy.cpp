// Cross-check against SciPy (tests/spectral/scipy_reference.py): eigenvalues
// and random-walk band projections of an independent implementation.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "spectral/band_split.h"
#include "spectral/bands.h"
#include "spectral/spectral_test_graphs.h"

namespace {

std::vector<double> read_numbers(const std::string& path) {
  std::ifstream in(path);
  std::vector<double> v;
  for (double d; in >> d;) v.push_back(d);
  return v;
}

TEST(SpectralScipy, EigenvaluesAndBandsMatch) {
  const char* python = std::getenv("PLEAT_PYTHON");
  if (python == nullptr) FAIL() << "PLEAT_PYTHON not set (run through ctest)";
  // Sphere (repeated eigenvalues) + a grid panel + two isolated vertices.
  const auto mesh = pleat_test::concat(pleat_test::icosphere(2, 1.0f),
                                       pleat_test::grid(9, 7, 0.1f, Eigen::Vector3f(3, 0, 0)));
  const pleat::Csr graph = spectral_test::graph_of(mesh, 2);
  const pleat::Points3d x = spectral_test::positions_of(mesh, 2);
  const int n = graph.vertex_count();

  for (auto solver : {pleat::SolverKind::dense, pleat::SolverKind::slicing, pleat::SolverKind::hybrid}) {
    pleat::BandOptions options;
    options.solver = solver;
    const auto basis = pleat::compute_band_basis(graph, options);
    const std::string dir = pleat_test::temp_dir("spectral_scipy");
    {
      std::ofstream edges(dir + "/edges.txt"), positions(dir + "/positions.txt");
      edges.precision(17);
      positions.precision(17);
      for (int v = 0; v < n; ++v)
        for (int k = graph.offsets[v]; k < graph.offsets[v + 1]; ++k)
          if (graph.indices[k] > v) edges << v << ' ' << graph.indices[k] << '\n';
      for (int v = 0; v < n; ++v) positions << x(v, 0) << ' ' << x(v, 1) << ' ' << x(v, 2) << '\n';
    }
    const int count = static_cast<int>(basis.eigenvalues.size());
    std::string output;
    const std::string command =
        std::string(python) + " " + pleat_test::source_dir() + "/tests/spectral/scipy_reference.py " + dir +
        "/edges.txt " + dir + "/positions.txt " + std::to_string(n) + " " + std::to_string(count) + " " +
        std::to_string(basis.low_count) + " " + std::to_string(basis.mid_count) + " " + dir;
    ASSERT_EQ(pleat_test::run_command(command, &output), 0) << command << "\n" << output;

    const std::vector<double> values = read_numbers(dir + "/eigenvalues.txt");
    ASSERT_EQ(static_cast<int>(values.size()), count);
    for (int i = 0; i < count; ++i) EXPECT_NEAR(values[i], basis.eigenvalues[i], 1e-8) << i;

    pleat::Points3d low(n, 3), mid(n, 3);
    pleat::split_bands<double>(basis, x.data(), 1, 0, low.data(), 0, mid.data(), 0, nullptr, 0);
    const std::vector<double> ref_low = read_numbers(dir + "/low.txt");
    const std::vector<double> ref_mid = read_numbers(dir + "/mid.txt");
    ASSERT_EQ(ref_low.size(), static_cast<size_t>(3 * n));
    ASSERT_EQ(ref_mid.size(), static_cast<size_t>(3 * n));
    EXPECT_LT((low - Eigen::Map<const pleat::Points3d>(ref_low.data(), n, 3)).norm(), 1e-6 * x.norm());
    EXPECT_LT((mid - Eigen::Map<const pleat::Points3d>(ref_mid.data(), n, 3)).norm(), 1e-6 * x.norm());
  }
}

}  // namespace
