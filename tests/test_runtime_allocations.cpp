// evaluate() allocates nothing: this binary interposes the C allocator
// (every operator new, Eigen matrix and std::vector ends there), and a bound
// instance (two threads, every stage, every output, a prepared garment) must
// not call it while it evaluates.
#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>

#include "body/body.h"
#include "garment/garment.h"
#include "runtime/instance.h"
#include "runtime/model_init.h"
#include "spectral/bands.h"
#include "support/chain_fixtures.h"
#include "support/interposed_allocator.h"

namespace {

using namespace pleat;
using namespace pleat::runtime;

TEST(RuntimeAllocations, EvaluateAllocatesNothing) {
  if (!pleat_test::kAllocatorInterposed)
    GTEST_SKIP() << "the allocator cannot be interposed under AddressSanitizer (the Release build runs this)";
  const Body body = pleat_test::chain_body();

  // A 12 x 12 grid garment, prepared (bands), and a small model with an
  // offset filter.
  const int side = 12;
  Points3d v(side * side, 3);
  Triangles t(2 * (side - 1) * (side - 1), 3);
  int k = 0;
  for (int r = 0; r < side; ++r)
    for (int c = 0; c < side; ++c) v.row(r * side + c) << -0.3 + 0.05 * c, 0.8 + 0.05 * r, 0.15;
  for (int r = 0; r + 1 < side; ++r)
    for (int c = 0; c + 1 < side; ++c) {
      const int a = r * side + c;
      t.row(k++) << a, a + 1, a + side;
      t.row(k++) << a + 1, a + side + 1, a + side;
    }
  Garment g = build_garment(v, t, {}, "grid");
  g.prepared.emplace();
  g.prepared->bands = compute_band_basis(g.graph, BandOptions{}).cast<float>();
  const auto garment = std::make_shared<const Garment>(std::move(g));
  ModelInitOptions mo;
  mo.code_width = 16;
  mo.body_widths = {16};
  mo.garment_widths = {16, 16};
  mo.offset_filter_length = 0.05f;  // the filter's solves run too
  const auto model = initialize_model({body.skeleton.names, body.skeleton.parents}, {}, mo);

  InstanceOptions io;
  io.threads = 2;
  io.max_batch = 4;
  Instance instance(model, garment, body, io);
  const int n = instance.vertex_count(), frames = 10;
  std::vector<float> rotations, roots;
  for (int f = 0; f < frames; ++f) {
    for (int j = 0; j < 3; ++j) {
      const Eigen::Quaternionf q(Eigen::AngleAxisf(0.1f * f * (j + 1), Eigen::Vector3f::UnitZ()));
      rotations.insert(rotations.end(), {q.x(), q.y(), q.z(), q.w()});
    }
    roots.insert(roots.end(), {0.02f * f, 1.0f, 0.0f});
  }
  const PoseSequence poses{rotations.data(), roots.data(), frames, 3, 30.0};
  std::vector<float> positions(frames * n * 3), normals(positions.size()), low(positions.size()),
      mid(positions.size()), high(positions.size()), weights(frames * n * 3);
  EvaluateOutputs out;
  out.positions = {positions.data(), size_t(n) * 3};
  out.normals = {normals.data(), size_t(n) * 3};
  out.skinning_weights = {weights.data(), size_t(n) * 3};
  out.low = {low.data(), size_t(n) * 3};
  out.mid = {mid.data(), size_t(n) * 3};
  out.high = {high.data(), size_t(n) * 3};

  for (Stage stage : {Stage::skinning, Stage::blend_shapes, Stage::refinement}) {
    const long before = pleat_test::allocation_count();
    instance.evaluate(poses, 3, frames - 3, stage, out);
    EXPECT_EQ(pleat_test::allocation_count() - before, 0) << "stage " << int(stage);
  }
  {  // a held refinement with an attenuated band, starting inside an interval
    const long before = pleat_test::allocation_count();
    EvaluateDetail detail;
    detail.interval = 3;
    detail.band_attenuation[2] = 0.5f;
    detail.body_collision = 0.003f;
    instance.evaluate(poses, 4, frames - 4, Stage::refinement, out, detail);
    EXPECT_EQ(pleat_test::allocation_count() - before, 0)
        << "refinement interval 3, high band halved, body-collision post-pass";
  }
  {  // with a vertex mask (the left half of the grid)
    std::vector<uint8_t> mask(size_t(n), 0);
    for (int v = 0; v < n; ++v) mask[size_t(v)] = v % side < side / 2;
    instance.set_vertex_mask(mask.data());
    ASSERT_EQ(instance.active_vertex_count(), n / 2);
    for (Stage stage : {Stage::blend_shapes, Stage::refinement}) {
      const long before = pleat_test::allocation_count();
      instance.evaluate(poses, 3, frames - 3, stage, out);
      EXPECT_EQ(pleat_test::allocation_count() - before, 0) << "vertex mask, stage " << int(stage);
    }
    instance.set_vertex_mask(nullptr);
  }
  // The counter works: binding allocates.
  const long before = pleat_test::allocation_count();
  Instance another(model, garment, body, io);
  EXPECT_GT(pleat_test::allocation_count() - before, 10);
}

}  // namespace
