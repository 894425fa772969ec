#include "spectral/band_split.h"

#include "core/error.h"

namespace pleat {

template <typename Scalar>
void split_bands(const BandBasis<Scalar>& basis, const Scalar* positions, size_t frame_count,
                 size_t in_stride, Scalar* low, size_t low_stride, Scalar* mid, size_t mid_stride,
                 Scalar* high, size_t high_stride, BandSplitScratch<Scalar>* scratch) {
  using Frame = Eigen::Map<const Eigen::Matrix<Scalar, Eigen::Dynamic, 3, Eigen::RowMajor>>;
  using OutFrame = Eigen::Map<Eigen::Matrix<Scalar, Eigen::Dynamic, 3, Eigen::RowMajor>>;
  const Eigen::Index n = basis.vertex_count;
  const Eigen::Index cols = 3 * static_cast<Eigen::Index>(frame_count);
  if (frame_count == 0 || (low == nullptr && mid == nullptr && high == nullptr)) return;
  if (positions == nullptr) fail(PLEAT_ERROR_INVALID_ARGUMENT, "positions: null");
  if (basis.vectors.rows() != n || basis.vectors.cols() != basis.mid_count)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "band basis: vectors do not match its counts");
  BandSplitScratch<Scalar> local;
  BandSplitScratch<Scalar>& s = scratch != nullptr ? *scratch : local;
  const bool random_walk = basis.projection == ProjectionForm::random_walk;

  // Gather all frames side by side (N x 3F, column-major) so the projection
  // is one GEMM for the batch instead of 3F thin matrix-vector products.
  // The scratch only grows: a smaller batch works in its leading columns,
  // so a caller that sized it once (an Instance) never allocates here.
  const Eigen::Index l = basis.low_count, m = basis.mid_count;
  using Matrix = typename BandSplitScratch<Scalar>::Matrix;
  const auto grow = [cols](Matrix& matrix, Eigen::Index rows) {
    if (matrix.rows() != rows || matrix.cols() < cols) matrix.resize(rows, cols);
  };
  grow(s.scaled, n);
  grow(s.coefficients, m);
  grow(s.low, n);
  grow(s.mid, n);
  auto scaled = s.scaled.leftCols(cols);
  auto coefficients = s.coefficients.leftCols(cols);
  auto low_part = s.low.leftCols(cols);
  auto mid_part = s.mid.leftCols(cols);
  for (size_t f = 0; f < frame_count; ++f) {
    const Frame x(positions + f * in_stride, n, 3);
    if (random_walk) {
      scaled.middleCols(3 * f, 3) = basis.sqrt_degree.asDiagonal() * x;
    } else {
      scaled.middleCols(3 * f, 3) = x;
    }
  }
  coefficients.noalias() = basis.vectors.transpose() * scaled;
  // X^l = U_l C_l and X^m = U_(l..m) C_(l..m) (= U_m C_m - X^l): the rows of C
  // are shared, so low + mid cost one N x m x 3F product in total.
  low_part.noalias() = basis.vectors.leftCols(l) * coefficients.topRows(l);
  mid_part.noalias() = basis.vectors.middleCols(l, m - l) * coefficients.middleRows(l, m - l);
  for (size_t f = 0; f < frame_count; ++f) {
    const Frame x(positions + f * in_stride, n, 3);
    auto xl = low_part.middleCols(3 * f, 3);
    auto xm = mid_part.middleCols(3 * f, 3);
    if (random_walk) {
      // Undo the D^{1/2} scaling: rows divided by sqrt_degree.
      xl = basis.sqrt_degree.cwiseInverse().asDiagonal() * xl;
      xm = basis.sqrt_degree.cwiseInverse().asDiagonal() * xm;
    }
    if (low != nullptr) OutFrame(low + f * low_stride, n, 3) = xl;
    if (mid != nullptr) OutFrame(mid + f * mid_stride, n, 3) = xm;
    if (high != nullptr) OutFrame(high + f * high_stride, n, 3) = x - (xl + xm);
  }
}

template void split_bands<float>(const BandBasis<float>&, const float*, size_t, size_t, float*, size_t,
                                 float*, size_t, float*, size_t, BandSplitScratch<float>*);
template void split_bands<double>(const BandBasis<double>&, const double*, size_t, size_t, double*, size_t,
                                  double*, size_t, double*, size_t, BandSplitScratch<double>*);

}  // namespace pleat
