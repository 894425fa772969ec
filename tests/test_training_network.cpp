// Parity of the trainer's network with the runtime: the same model, garment,
// body and poses give the same positions (within 1e-4 of the garment's
// bounding-box diagonal) at every stage, for a freshly initialised model and
// for one whose every parameter has been moved by training steps and which
// went through a model file; and the MakeHuman body with the sample dress
// at the initialiser's full architecture.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "body/bvh.h"
#include "body/makehuman.h"
#include "body/motion_ops.h"
#include "garment/garment.h"
#include "io/mesh_import.h"
#include "network.h"
#include "offset_filter_op.h"
#include "runtime/instance.h"
#include "runtime/model_file.h"
#include "runtime/model_init.h"
#include "support/chain_fixtures.h"
#include "support/test_support.h"

using namespace pleat;
using namespace pleat::runtime;

namespace {

std::shared_ptr<const Garment> grid_garment(int side) {
  Points3d v(side * side, 3);
  Triangles t(2 * (side - 1) * (side - 1), 3);
  int k = 0;
  for (int r = 0; r < side; ++r)
    for (int c = 0; c < side; ++c)
      v.row(r * side + c) << -0.3 + 0.6 * c / (side - 1), 0.8 + 0.6 * r / (side - 1),
          0.15 + 0.02 * std::sin(c + r);
  for (int r = 0; r + 1 < side; ++r)
    for (int c = 0; c + 1 < side; ++c) {
      const int a = r * side + c;
      t.row(k++) << a, a + 1, a + side;
      t.row(k++) << a + 1, a + side + 1, a + side;
    }
  return std::make_shared<const Garment>(build_garment(v, t, {}, "grid"));
}

struct Clip {
  std::vector<float> rotations, roots;
  int32_t joints = 0;
  PoseSequence poses(int64_t frames) const { return {rotations.data(), roots.data(), frames, joints, 30.0}; }
};

Clip turning_clip(int frames) {
  Clip c;
  c.joints = 3;
  for (int f = 0; f < frames; ++f) {
    for (int j = 0; j < 3; ++j) {
      const Eigen::Quaternionf q(
          Eigen::AngleAxisf(0.25f * f, j == 0 ? Eigen::Vector3f::UnitY() : Eigen::Vector3f::UnitZ()));
      c.rotations.insert(c.rotations.end(), {q.x(), q.y(), q.z(), q.w()});
    }
    c.roots.insert(c.roots.end(), {0.03f * f, 1.0f, 0.02f * f});
  }
  return c;
}

Clip clip_of(const Motion& m, int frames) {
  Clip c;
  c.joints = m.skeleton.joint_count();
  for (int f = 0; f < frames; ++f) {
    for (int j = 0; j < c.joints; ++j) {
      const Eigen::Quaterniond& q = m.frame(f)[j];
      c.rotations.insert(c.rotations.end(), {float(q.x()), float(q.y()), float(q.z()), float(q.w())});
    }
    for (int k = 0; k < 3; ++k) c.roots.push_back(float(m.root_translation(f, k)));
  }
  return c;
}

double diagonal(const Garment& g) {
  return (g.rest.vertices.colwise().maxCoeff() - g.rest.vertices.colwise().minCoeff()).norm();
}

// Largest |trainer - runtime| over frames and stages, relative to the diagonal.
double parity(const std::shared_ptr<const Model>& model, training::Network& network,
              const std::shared_ptr<const Garment>& garment, const Body& body, const Clip& clip,
              const std::vector<int64_t>& frames) {
  training::BoundGarment bound(*model, garment, body);
  InstanceOptions options;
  options.top_k = model->joint_count();  // exact softmax, as in training
  Instance instance(model, garment, body, options);
  const int64_t total = frames.back() + 1;
  const PoseSequence poses = clip.poses(total);
  const int n = instance.vertex_count();
  double worst = 0;
  torch::NoGradGuard no_grad;
  for (Stage stage : {Stage::skinning, Stage::blend_shapes, Stage::refinement}) {
    const torch::Tensor got = network->forward(bound, poses, frames, stage).positions.contiguous();
    for (size_t i = 0; i < frames.size(); ++i) {
      std::vector<float> want(size_t(n) * 3);
      EvaluateOutputs out;
      out.positions = {want.data(), size_t(n) * 3};
      instance.evaluate(poses, frames[i], 1, stage, out);
      const float* g = got[static_cast<int64_t>(i)].data_ptr<float>();
      for (size_t k = 0; k < want.size(); ++k) worst = std::max(worst, double(std::abs(g[k] - want[k])));
    }
  }
  std::printf("trainer vs runtime: %.3g of the bounding-box diagonal\n", worst / diagonal(*garment));
  return worst / diagonal(*garment);
}

ModelInitOptions small_options() {
  ModelInitOptions o;
  o.code_width = 16;
  o.body_widths = {16, 16};
  o.garment_widths = {16, 16};
  o.gru_layers = 2;
  o.blend_widths = {16, 3};
  o.refinement_widths = {16, 8, 3};
  o.window_frames = 4;
  return o;
}

}  // namespace

TEST(TrainingNetwork, FreshModelMatchesTheRuntime) {
  const Body body = pleat_test::chain_body();
  const auto garment = grid_garment(8);
  for (auto variant :
       {nn::AttentionVariant::gat, nn::AttentionVariant::lgat, nn::AttentionVariant::flexigat}) {
    ModelInitOptions o = small_options();
    o.variant = variant;
    const auto model = initialize_model({body.skeleton.names, body.skeleton.parents}, {}, o);
    training::Network network(*model);
    EXPECT_LT(parity(model, network, garment, body, turning_clip(9), {0, 3, 8}), 1e-4) << int(variant);
  }
}

// The refinement reading F^t (Feature::fused_code): the trainer and the
// runtime agree, the file keeps the feature (format version 5), and the
// runtime reads each frame's own motion code whatever the split into calls:
// in a batch (row b), for a frame before the call (an interval's held frame,
// the spare row).
TEST(TrainingNetwork, RefinementReadingTheFusedCodeMatchesTheRuntime) {
  const Body body = pleat_test::chain_body();
  const auto garment = grid_garment(8);
  ModelInitOptions o = small_options();
  o.refinement_features = {Feature::velocity, Feature::fused_code, Feature::posed_joint_distances};
  const auto model = initialize_model({body.skeleton.names, body.skeleton.parents}, {}, o);
  EXPECT_EQ(model->refinement.in_width(), 3 + o.code_width + model->joint_count());
  const std::string path = pleat_test::temp_dir("training_network") + "/fused_code.pleat";
  save_model(*model, path);
  const std::shared_ptr<const Model> loaded = load_model_file(path);
  EXPECT_EQ(model_format_version(*loaded), 5u);
  EXPECT_EQ(loaded->refinement.features, o.refinement_features);
  training::Network network(*loaded);
  const Clip clip = turning_clip(9);
  EXPECT_LT(parity(loaded, network, garment, body, clip, {0, 3, 8}), 1e-4);

  // The same model without the code's columns differs: the runtime reads them.
  std::shared_ptr<Model> blind = std::make_shared<Model>(*loaded);
  blind->refinement.layers.front().weight.middleRows(3, o.code_width).setZero();
  validate_model(*blind);

  const PoseSequence poses = clip.poses(9);
  const int n = garment->rest.vertex_count();
  const auto evaluate = [&](const std::shared_ptr<const Model>& m, int64_t first, int64_t count,
                            int32_t interval, int32_t max_batch) {
    InstanceOptions options;
    options.max_batch = max_batch;
    Instance instance(m, garment, body, options);
    std::vector<float> out(size_t(count) * n * 3);
    EvaluateOutputs outputs;
    outputs.positions = {out.data(), size_t(n) * 3};
    EvaluateDetail detail;
    detail.interval = interval;
    instance.evaluate(poses, first, count, Stage::refinement, outputs, detail);
    return out;
  };
  const std::vector<float> whole = evaluate(loaded, 0, 9, 1, 4);
  EXPECT_NE(evaluate(blind, 0, 9, 1, 4), whole);
  std::vector<float> one_by_one;
  for (int64_t t = 0; t < 9; ++t) {
    const std::vector<float> frame = evaluate(loaded, t, 1, 1, 1);
    one_by_one.insert(one_by_one.end(), frame.begin(), frame.end());
  }
  EXPECT_EQ(one_by_one, whole);
  const std::vector<float> held = evaluate(loaded, 0, 9, 3, 4);
  const std::vector<float> from_inside = evaluate(loaded, 4, 5, 3, 4);
  EXPECT_EQ(from_inside, std::vector<float>(held.begin() + 4 * n * 3, held.end()));
}

// With an offset filter (h = 0.1 m against 8.6 cm edges): training runs
// through its backward, and the file keeps h.
TEST(TrainingNetwork, TrainedAndExportedModelMatchesTheRuntime) {
  const Body body = pleat_test::chain_body();
  const auto garment = grid_garment(8);
  ModelInitOptions options = small_options();
  options.offset_filter_length = 0.1f;
  const auto model = initialize_model({body.skeleton.names, body.skeleton.parents}, {}, options);
  training::Network network(*model);
  training::BoundGarment bound(*model, garment, body);
  const Clip clip = turning_clip(9);
  const PoseSequence poses = clip.poses(9);
  // Pull the output towards a shifted, scaled copy: every parameter moves.
  torch::optim::Adam optimizer(network->parameters(), torch::optim::AdamOptions(3e-2));
  const std::vector<int64_t> frames = {2, 5, 8};
  const torch::Tensor target = bound.rest.unsqueeze(0).expand({3, -1, -1}) * 1.1 + 0.05;
  std::vector<torch::Tensor> before;
  for (const torch::Tensor& p : network->parameters()) before.push_back(p.detach().clone());
  for (int step = 0; step < 20; ++step) {
    optimizer.zero_grad();
    const torch::Tensor loss =
        (network->forward(bound, poses, frames, Stage::refinement).positions - target).pow(2).mean();
    loss.backward();
    optimizer.step();
  }
  size_t moved = 0, index = 0;
  for (const torch::Tensor& p : network->parameters()) moved += !torch::equal(p.detach(), before[index++]);
  EXPECT_GE(moved, network->parameters().size() - 0) << "every trainable parameter changed";

  const std::string path = pleat_test::temp_dir("training_network") + "/trained.pleat";
  save_model(*network->to_model(), path);
  const std::shared_ptr<const Model> loaded = load_model_file(path);
  EXPECT_EQ(loaded->offset_filter_length, 0.1f);
  EXPECT_LT(parity(loaded, network, garment, body, clip, {0, 4, 8}), 1e-4);
}

// x = A^{-1} d with A = I + L symmetric: the op's forward and its gradient
// of <x, g> (A^{-1} g) against a dense solve of A assembled here.
TEST(TrainingNetwork, OffsetFilterOpAndItsGradientMatchADenseSolve) {
  const auto garment = grid_garment(5);
  const double h = 0.2;
  const runtime::OffsetFilter filter(*garment, h);
  const int64_t n = garment->rest.vertex_count();
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(n, n);
  for (const Edge& e : garment->edges) {
    const double w =
        std::pow(h / (garment->rest.vertices.row(e.a) - garment->rest.vertices.row(e.b)).norm(), 2);
    a(e.a, e.a) += w;
    a(e.b, e.b) += w;
    a(e.a, e.b) -= w;
    a(e.b, e.a) -= w;
  }
  const Eigen::LDLT<Eigen::MatrixXd> solver(a);
  torch::manual_seed(3);
  const torch::Tensor d = torch::randn({2, n, 3}).requires_grad_(true), g = torch::randn({2, n, 3});
  const torch::Tensor x = training::filter_offsets(d, filter);
  (x * g).sum().backward();
  const auto dense_solve = [&](const torch::Tensor& t, int64_t frame) {
    Eigen::MatrixXd rhs(n, 3);
    for (int64_t v = 0; v < n; ++v)
      for (int64_t c = 0; c < 3; ++c) rhs(v, c) = t[frame][v][c].item<float>();
    return Eigen::MatrixXd(solver.solve(rhs));
  };
  for (int64_t f = 0; f < 2; ++f) {
    const Eigen::MatrixXd want_x = dense_solve(d.detach(), f), want_grad = dense_solve(g, f);
    for (int64_t v = 0; v < n; ++v)
      for (int64_t c = 0; c < 3; ++c) {
        EXPECT_NEAR(x[f][v][c].item<float>(), want_x(v, c), 1e-5);
        EXPECT_NEAR(d.grad()[f][v][c].item<float>(), want_grad(v, c), 1e-5);
      }
  }
  EXPECT_GT((x - d).abs().max().item<float>(), 0.1f) << "the filter changes the field";
}

TEST(TrainingNetwork, MakeHumanDressAtTheFullArchitectureMatchesTheRuntime) {
  const Body body = MakeHumanModel::load(pleat_test::asset_dir() + "/body")->body(makehuman_default_beta());
  const ImportedMesh mesh = import_mesh(pleat_test::source_dir() + "/data/garments/female_elegantsuit01.obj");
  GarmentBuildOptions go;
  go.unit_scale = 0.1;
  const auto garment =
      std::make_shared<const Garment>(build_garment(mesh.vertices, mesh.triangles, go, "dress"));
  ModelSkeleton skeleton{body.skeleton.names, body.skeleton.parents};
  std::vector<ShapeEntry> shape;
  for (const ShapeParameter& p : body.shape) shape.push_back({p.name, float(p.default_value)});
  const auto model = initialize_model(skeleton, shape, ModelInitOptions{});
  const Motion walk = retarget_motion(
      resample_motion(read_bvh(pleat_test::source_dir() + "/tests/fixtures/motion/12_03_walk_121.bvh").motion,
                      30.0),
      body.skeleton);
  training::Network network(*model);
  EXPECT_LT(parity(model, network, garment, body, clip_of(walk, 12), {0, 11}), 1e-4);
}
