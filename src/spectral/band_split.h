#pragma once
// Splits vertex positions into low / mid / high frequency bands with a band
// basis, batched over frames (the basis is computed once per garment).
#include <cstddef>

#include "spectral/bands.h"

namespace pleat {

// Reusable work memory for split_bands; grows to the largest call and is
// kept (smaller calls use its leading columns and allocate nothing).
template <typename Scalar>
struct BandSplitScratch {
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  Matrix scaled;        // N x 3F: positions (times sqrt_degree for random walk)
  Matrix coefficients;  // mid_count x 3F: U_m^T scaled
  Matrix low;           // N x 3F: U_l C_l
  Matrix mid;           // N x 3F: U_(l..m) C_(l..m)
};

// positions: frame f is N x 3 row-major xyz at positions + f * in_stride.
// low / mid / high (each may be nullptr to skip) are written the same way
// with their own strides. Symmetric form:
//   X^l = U_l U_l^T X,  X^m = U_m U_m^T X - X^l,  X^h = X - X^l - X^m;
// random-walk form: the same with P = D^{-1/2} U U^T D^{1/2}. high is X minus
// the other two, so X = X^l + X^m + X^h to round-off. Cost: two GEMMs over
// all frames at once. `scratch` may be nullptr (allocated for this call).
template <typename Scalar>
void split_bands(const BandBasis<Scalar>& basis, const Scalar* positions, size_t frame_count,
                 size_t in_stride, Scalar* low, size_t low_stride, Scalar* mid, size_t mid_stride,
                 Scalar* high, size_t high_stride, BandSplitScratch<Scalar>* scratch = nullptr);

}  // namespace pleat
