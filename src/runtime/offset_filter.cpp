#include "runtime/offset_filter.h"

#include <algorithm>
#include <string>
#include <vector>

#include "capi/pleat.h"
#include "core/error.h"

namespace pleat::runtime {

OffsetFilter::OffsetFilter(const Garment& garment, double length) {
  const int32_t n = garment.rest.vertex_count();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(garment.edges.size() * 4 + n);
  for (int32_t v = 0; v < n; ++v) entries.emplace_back(v, v, 1.0);
  for (const Edge& e : garment.edges) {
    const double l = (garment.rest.vertices.row(e.a) - garment.rest.vertices.row(e.b)).norm();
    const double ratio = length / std::max(l, kOffsetFilterShortestEdge * length);
    const double w = ratio * ratio;
    entries.emplace_back(e.a, e.a, w);
    entries.emplace_back(e.b, e.b, w);
    entries.emplace_back(e.a, e.b, -w);
    entries.emplace_back(e.b, e.a, -w);
  }
  Eigen::SparseMatrix<double> system(n, n);
  system.setFromTriplets(entries.begin(), entries.end());
  ldlt_.compute(system);
  // I + L is symmetric positive definite, so this only fails on exhaustion.
  if (ldlt_.info() != Eigen::Success)
    fail(PLEAT_ERROR_NUMERICAL, "garment '" + garment.source + "': the offset filter's LDLT failed");
  inverse_pivots_ = ldlt_.vectorD().cwiseInverse();
  permuted_.setZero(n);
}

void OffsetFilter::apply(float* offsets, int64_t frames) const {
  const int32_t n = vertex_count();
  const auto& order = ldlt_.permutationP().indices();  // (P b)[order[i]] = b[i]
  for (int64_t f = 0; f < frames; ++f) {
    float* field = offsets + f * n * 3;
    for (int c = 0; c < 3; ++c) {
      for (int32_t v = 0; v < n; ++v) permuted_[order[v]] = field[v * 3 + c];
      ldlt_.matrixL().solveInPlace(permuted_);
      permuted_.array() *= inverse_pivots_.array();
      ldlt_.matrixU().solveInPlace(permuted_);
      for (int32_t v = 0; v < n; ++v) field[v * 3 + c] = static_cast<float>(permuted_[order[v]]);
    }
  }
}

}  // namespace pleat::runtime
