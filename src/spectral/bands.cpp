#include "spectral/bands.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/topology.h"
#include "spectral/eigensolver.h"
#include "spectral/laplacian.h"

namespace pleat {
namespace {

// Eigenpairs solved beyond the requested mid cut, to see the gap above it.
constexpr int kMinMargin = 8;
constexpr int kMarginDivisor = 50;

void check_fraction(double value, const char* field) {
  if (!(value > 0.0 && value <= 1.0))
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         std::string(field) + " must be in (0, 1], got " + std::to_string(value));
}

// ceil(N * f), forgiving the round-off of f = 1/30 and the like (N * f a hair
// above an integer must not add an eigenvector), clamped to [1, N].
int requested_count(int n, double fraction) {
  const double exact = n * fraction;
  const int count = static_cast<int>(std::ceil(exact - 1e-9 * std::max(1.0, exact)));
  return std::clamp(count, 1, n);
}

double gap_at(const Eigen::VectorXd& values, int n, int cut) {
  if (cut >= n) return std::numeric_limits<double>::infinity();
  return values[cut] - values[cut - 1];
}

}  // namespace

void validate_band_options(const BandOptions& options) {
  check_fraction(options.low_fraction, "low_fraction");
  check_fraction(options.mid_fraction, "mid_fraction");
  if (options.low_fraction > options.mid_fraction)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "low_fraction (" + std::to_string(options.low_fraction) +
                                           ") must not exceed mid_fraction (" +
                                           std::to_string(options.mid_fraction) + ")");
  const auto solver = static_cast<uint32_t>(options.solver);
  if (solver > PLEAT_SOLVER_HYBRID)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "solver: unknown value " + std::to_string(solver));
  const auto projection = static_cast<uint32_t>(options.projection);
  if (projection != PLEAT_PROJECTION_RANDOM_WALK && projection != PLEAT_PROJECTION_SYMMETRIC)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "projection: unknown value " + std::to_string(projection));
}

int nearest_gap_cut(const Eigen::VectorXd& values, int vertex_count, int requested, int min_cut,
                    double min_gap) {
  const int known = static_cast<int>(values.size());
  const int start = std::max(requested, min_cut);
  // A cut k needs lambda[k]: known for k < known, or k == N (nothing above).
  auto knowable = [&](int k) { return k < known || k == vertex_count; };
  for (int distance = 0;; ++distance) {
    const int up = start + distance, down = start - distance;
    if (up <= vertex_count) {
      if (!knowable(up)) return -1;
      if (gap_at(values, vertex_count, up) >= min_gap) return up;
    }
    if (down >= min_cut && down != up && gap_at(values, vertex_count, down) >= min_gap) return down;
  }
}

BandBasis<double> compute_band_basis(const Csr& graph, const BandOptions& options) {
  validate_band_options(options);
  const int n = graph.vertex_count();
  if (n < 1) fail(PLEAT_ERROR_INVALID_ARGUMENT, "graph: no vertices");
  std::vector<int32_t> labels;
  const int components = connected_components(graph, &labels);

  BandBasis<double> basis;
  basis.vertex_count = n;
  basis.low_requested = requested_count(n, options.low_fraction);
  basis.mid_requested = requested_count(n, options.mid_fraction);
  basis.solver = resolve_solver(options.solver, n);
  basis.projection = options.projection;

  const Eigen::SparseMatrix<double> laplacian = normalized_laplacian(graph);
  const int margin = std::max(kMinMargin, basis.mid_requested / kMarginDivisor);
  int count = std::min(n, std::max(basis.mid_requested, components) + margin);
  EigenPairs pairs;
  for (;;) {
    pairs = solve_lowest(laplacian, count, basis.solver);
    // Every zero eigenvalue (one per component) stays in the low band.
    basis.low_count = nearest_gap_cut(pairs.values, n, basis.low_requested, components, kMinGap);
    basis.mid_count = basis.low_count < 0
                          ? -1
                          : nearest_gap_cut(pairs.values, n, basis.mid_requested, basis.low_count, kMinGap);
    if (basis.mid_count >= 0) break;
    count = std::min(n, count + 2 * margin + count / 4);  // no gap in the margin: see further
  }
  basis.low_gap = gap_at(pairs.values, n, basis.low_count);
  basis.mid_gap = gap_at(pairs.values, n, basis.mid_count);
  basis.eigenvalues = pairs.values.head(std::min(basis.mid_count + 1, n));
  basis.vectors = pairs.vectors.leftCols(basis.mid_count);
  basis.sqrt_degree = sqrt_degree(graph);
  return basis;
}

}  // namespace pleat
