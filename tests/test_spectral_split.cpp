// Band split: exact partition, projections, translation invariance of the
// random-walk form, batching with strides.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "spectral/band_split.h"
#include "spectral/bands.h"
#include "spectral/spectral_test_graphs.h"

namespace {

using pleat::ProjectionForm;

struct Split {
  pleat::Points3d low, mid, high;
};

// Grid: boundary vertices have degree 2-4, interior 6 (non-uniform D).
const pleat_test::SimpleMesh& mesh() {
  static const pleat_test::SimpleMesh m = pleat_test::grid(20, 16, 0.05f);
  return m;
}

pleat::BandBasis<double> basis(ProjectionForm form) {
  pleat::BandOptions options;
  options.solver = pleat::SolverKind::dense;
  options.projection = form;
  return pleat::compute_band_basis(spectral_test::graph_of(mesh()), options);
}

// Positions with some wrinkles so every band is non-trivial.
pleat::Points3d wavy() {
  pleat::Points3d x = spectral_test::positions_of(mesh());
  for (Eigen::Index v = 0; v < x.rows(); ++v)
    x(v, 2) = 0.1 * std::sin(3.0 * x(v, 0)) + 0.01 * std::sin(40.0 * x(v, 1) + 7.0 * x(v, 0));
  return x;
}

Split split(const pleat::BandBasis<double>& b, const pleat::Points3d& x) {
  Split s{pleat::Points3d(x.rows(), 3), pleat::Points3d(x.rows(), 3), pleat::Points3d(x.rows(), 3)};
  pleat::split_bands<double>(b, x.data(), 1, 0, s.low.data(), 0, s.mid.data(), 0, s.high.data(), 0);
  return s;
}

TEST(SpectralSplit, BandsSumToInputDouble) {
  for (auto form : {ProjectionForm::random_walk, ProjectionForm::symmetric}) {
    const pleat::Points3d x = wavy();
    const Split s = split(basis(form), x);
    EXPECT_LT((s.low + s.mid + s.high - x).norm(), 1e-14 * x.norm());
    EXPECT_GT(s.mid.norm(), 1e-3 * x.norm());
    EXPECT_GT(s.high.norm(), 1e-5 * x.norm());
  }
}

TEST(SpectralSplit, BandsSumToInputFloat) {
  for (auto form : {ProjectionForm::random_walk, ProjectionForm::symmetric}) {
    const pleat::BandBasis<float> b = basis(form).cast<float>();
    const pleat::Points3f x = wavy().cast<float>();
    pleat::Points3f low(x.rows(), 3), mid(x.rows(), 3), high(x.rows(), 3);
    pleat::split_bands<float>(b, x.data(), 1, 0, low.data(), 0, mid.data(), 0, high.data(), 0);
    EXPECT_LT((low + mid + high - x).norm(), 1e-6f * x.norm());
    // float agrees with double to single precision.
    const Split d = split(basis(form), wavy());
    EXPECT_LT((mid.cast<double>() - d.mid).norm(), 1e-5 * d.mid.norm());
  }
}

TEST(SpectralSplit, ProjectionsAreIdempotent) {
  for (auto form : {ProjectionForm::random_walk, ProjectionForm::symmetric}) {
    const auto b = basis(form);
    const pleat::Points3d x = wavy();
    const Split s = split(b, x);
    const Split of_low = split(b, s.low);  // P_l P_l X = P_l X
    EXPECT_LT((of_low.low - s.low).norm(), 1e-12 * x.norm());
    EXPECT_LT(of_low.mid.norm() + of_low.high.norm(), 1e-12 * x.norm());
    const Split of_mid = split(b, s.mid);
    EXPECT_LT((of_mid.mid - s.mid).norm(), 1e-12 * x.norm());
    EXPECT_LT(of_mid.low.norm() + of_mid.high.norm(), 1e-12 * x.norm());
    const Split of_high = split(b, s.high);
    EXPECT_LT((of_high.high - s.high).norm(), 1e-12 * x.norm());
  }
}

TEST(SpectralSplit, TranslationStaysLowOnlyInRandomWalkForm) {
  const pleat::Points3d x = wavy();
  const Eigen::RowVector3d shift(10.0, -3.0, 5.0);
  const pleat::Points3d moved = x.rowwise() + shift;
  const Split rw = split(basis(ProjectionForm::random_walk), x);
  const Split rw_moved = split(basis(ProjectionForm::random_walk), moved);
  EXPECT_LT((rw_moved.mid - rw.mid).norm(), 1e-12 * moved.norm());
  EXPECT_LT((rw_moved.high - rw.high).norm(), 1e-12 * moved.norm());
  EXPECT_LT((rw_moved.low - rw.low).rowwise().operator-(shift).norm(), 1e-12 * moved.norm());

  // The paper-exact form's null vector is D^{1/2} 1, not 1: a translation
  // leaks into mid and high wherever degrees differ (the boundary here).
  const Split sym = split(basis(ProjectionForm::symmetric), x);
  const Split sym_moved = split(basis(ProjectionForm::symmetric), moved);
  const double leak_high = (sym_moved.high - sym.high).norm();
  const double leak_mid = (sym_moved.mid - sym.mid).norm();
  std::printf(
      "symmetric form, shift |t| = %.2f on %zu vertices: |dX^h| = %.3f (|X^h| = %.3f), "
      "|dX^m| = %.3f\n",
      shift.norm(), mesh().vertex_count(), leak_high, sym.high.norm(), leak_mid);
  EXPECT_GT(leak_high, 1e-2 * shift.norm());
}

TEST(SpectralSplit, BatchedStridesAndSkippedOutputs) {
  const auto b = basis(ProjectionForm::random_walk);
  const pleat::Points3d x = wavy();
  const size_t n3 = static_cast<size_t>(x.size());
  const size_t frames = 3, in_stride = n3 + 5, out_stride = n3 + 2;
  std::vector<double> in(frames * in_stride, -1.0), high(frames * out_stride, -7.0), low(frames * n3);
  for (size_t f = 0; f < frames; ++f)
    for (size_t i = 0; i < n3; ++i) in[f * in_stride + i] = x.data()[i] * (1.0 + f);
  pleat::BandSplitScratch<double> scratch;
  for (int repeat = 0; repeat < 2; ++repeat) {  // scratch reuse gives the same result
    pleat::split_bands<double>(b, in.data(), frames, in_stride, low.data(), n3, nullptr, 0, high.data(),
                               out_stride, &scratch);
    const Split one = split(b, x);
    for (size_t f = 0; f < frames; ++f) {
      Eigen::Map<const pleat::Points3d> hf(high.data() + f * out_stride, x.rows(), 3);
      Eigen::Map<const pleat::Points3d> lf(low.data() + f * n3, x.rows(), 3);
      EXPECT_LT((hf - (1.0 + f) * one.high).norm(), 1e-13 * x.norm() * (1.0 + f));
      EXPECT_LT((lf - (1.0 + f) * one.low).norm(), 1e-13 * x.norm() * (1.0 + f));
      EXPECT_EQ(high[f * out_stride + n3], -7.0);  // padding untouched
    }
  }
}

}  // namespace
