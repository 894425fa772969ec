// The trainer end to end on a small synthetic data set written in the
// sequence format: the MakeHuman body walks (the CMU fixture clip); the
// "simulated" skirt is the body's own skinning of the skirt pushed 2 cm
// outwards, which the untrained model does not know. Training must cut
// E_verts by at least 10x; a run resumed from its checkpoint must continue
// exactly as an uninterrupted one; the exported model must reproduce the
// trainer in the runtime.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "body/makehuman.h"
#include "body/motion_ops.h"
#include "capi/pleat.h"
#include "io/bvh.h"
#include "io/sequence.h"
#include "metrics/nearest_points.h"
#include "runtime/model_file.h"
#include "support/test_support.h"
#include "trainer.h"

using namespace pleat;
using namespace pleat::training;

namespace {

// An open cylinder of rings x segments vertices around the hips.
TriMesh skirt(double hip_height) {
  const int rings = 5, segments = 16;
  TriMesh m;
  m.vertices.resize(rings * segments, 3);
  const double pi = std::acos(-1.0);
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * pi * s / segments, y = hip_height + 0.05 - 0.3 * r / (rings - 1);
      const double radius = 0.2 + 0.06 * r / (rings - 1);
      m.vertices.row(r * segments + s) << radius * std::sin(a), y, radius * std::cos(a) + 0.01;
    }
  m.triangles.resize((rings - 1) * segments * 2, 3);
  int k = 0;
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      m.triangles.row(k++) << a, a + segments, b;
      m.triangles.row(k++) << b, a + segments, b + segments;
    }
  return m;
}

// Writes the data set: one 31-frame sequence.
std::string write_data(const std::string& root) {
  const std::string body_dir = pleat_test::asset_dir() + "/body";
  const Body body = MakeHumanModel::load(body_dir)->body(makehuman_default_beta());
  const Motion walk = retarget_motion(
      resample_motion(read_bvh(pleat_test::source_dir() + "/tests/fixtures/motion/12_03_walk_121.bvh").motion,
                      30.0),
      body.skeleton);
  const TriMesh rest = skirt(body.skeleton.rest_translation(0, 1));
  // Ground truth: the skirt pushed 2 cm outwards, skinned with the weights of
  // the nearest body vertex (what the model's skinning prior starts from).
  Points3d pushed = rest.vertices;
  for (Eigen::Index v = 0; v < pushed.rows(); ++v) {
    Eigen::Vector3d radial(pushed(v, 0), 0, pushed(v, 2) - 0.01);
    pushed.row(v) += 0.02 * radial.normalized().transpose();
  }
  const std::vector<int32_t> nearest = nearest_points(body.rest.vertices, rest.vertices);
  SkinWeights weights;
  weights.joint_count = body.joint_count();
  for (int32_t b : nearest) {
    for (int32_t k = body.weights.offsets[b]; k < body.weights.offsets[b + 1]; ++k) {
      weights.joints.push_back(body.weights.joints[k]);
      weights.weights.push_back(body.weights.weights[k]);
    }
    weights.offsets.push_back(static_cast<int32_t>(weights.joints.size()));
  }
  SequenceData d;
  d.meta.frame_rate = 30.0;
  d.meta.frame_count = walk.frame_count;
  d.meta.garment_name = "skirt";
  d.meta.garment_source = "synthetic";
  d.meta.body_source = body_dir;
  d.meta.body_kind = PLEAT_BODY_MAKEHUMAN;
  d.meta.body_rig = PLEAT_RIG_CMU_MB;
  d.meta.motion_source = "12_03_walk_121.bvh";
  d.meta.joint_names = body.skeleton.names;
  d.meta.simulator_json = R"({"name": "synthetic: pushed skirt, body skinning"})";
  d.garment_rest = rest;
  SkinningWorkspace ws;
  d.garment_frames.resize(static_cast<size_t>(walk.frame_count * rest.vertex_count() * 3));
  const Points3f pushed_f = pushed.cast<float>();
  skin_frames(pushed_f, weights, walk, 0, walk.frame_count, &ws, d.garment_frames.data(),
              d.garment_frames.size());
  const Points3d posed = pose_body_frames(body, walk, 0, walk.frame_count);
  d.body_frames.assign(posed.data(), posed.data() + posed.size());
  for (int64_t f = 0; f < walk.frame_count; ++f) {
    for (int32_t j = 0; j < body.joint_count(); ++j) {
      const Eigen::Quaterniond& q = walk.frame(f)[j];
      d.rotations.insert(d.rotations.end(), {float(q.x()), float(q.y()), float(q.z()), float(q.w())});
    }
    for (int k = 0; k < 3; ++k) d.root_positions.push_back(float(walk.root_translation(f, k)));
  }
  const std::string dir = root + "/skirt_walk";
  write_sequence(dir, d);
  return dir;
}

TrainerConfig config(const std::string& data, const std::string& output, int64_t epochs) {
  TrainerConfig c;
  c.train = {data};
  c.validation = {data};
  c.schedule = parse_schedule(R"({"phases": [{"name": "supervised",
      "weights": {"vertex": 100, "k_mid": 2, "k_high": 1.5, "edge": 15}}]})",
                              "test");
  c.output = output;
  c.epochs = epochs;
  c.batch_frames = 8;
  c.learning_rate = 1e-2;
  c.progress = false;
  c.model.code_width = 32;
  c.model.body_widths = {32, 32};
  c.model.garment_widths = {32, 32};
  c.model.gru_layers = 2;
  c.model.blend_widths = {32, 3};
  c.model.refinement_widths = {32, 16, 3};
  return c;
}

}  // namespace

TEST(TrainingLearns, SyntheticSkirtErrorDropsTenfoldAndTheExportMatches) {
  const std::string root = pleat_test::temp_dir("training_learns");
  const std::string data = write_data(root);
  Trainer trainer(config(data, root + "/run", 60));
  const double initial = trainer.validate(trainer.training_data()).e_verts_cm;
  const EpochResult last = trainer.run();
  std::printf("E_verts %.3f cm -> %.3f cm in %lld epochs, %.1f training frames/s\n", initial,
              last.validation.e_verts_cm, static_cast<long long>(last.epoch), last.frames_per_second);
  EXPECT_GT(initial, 1.0) << "the untrained model does not know the offset";
  EXPECT_LT(last.validation.e_verts_cm, initial / 10.0);
  EXPECT_TRUE(std::filesystem::exists(root + "/run/log.csv"));

  // The export reproduces the trainer in the runtime.
  const std::shared_ptr<runtime::Model> model = trainer.export_model();
  runtime::save_model(*model, root + "/run/model.pleat");
  const auto loaded = runtime::load_model_file(root + "/run/model.pleat");
  EXPECT_EQ(loaded->training.optimizer, "adamax");
  EXPECT_NEAR(loaded->training.metrics.front().value, last.validation.e_verts_cm, 1e-9);
  const TrainingSequence& s = trainer.training_data().sequences().front();
  runtime::InstanceOptions o;
  o.top_k = loaded->joint_count();
  runtime::Instance instance(loaded, s.garment, s.body, o);
  const int n = instance.vertex_count();
  std::vector<float> runtime_positions(size_t(n) * 3);
  runtime::EvaluateOutputs out;
  out.positions = {runtime_positions.data(), size_t(n) * 3};
  instance.evaluate(s.poses(), 20, 1, runtime::Stage::refinement, out);
  torch::NoGradGuard no_grad;
  BoundGarment bound(*loaded, s.garment, s.body);
  const torch::Tensor trained =
      trainer.network()->forward(bound, s.poses(), {20}, runtime::Stage::refinement).positions.contiguous();
  double worst = 0;
  for (int i = 0; i < n * 3; ++i)
    worst = std::max(worst, double(std::abs(trained.data_ptr<float>()[i] - runtime_positions[i])));
  EXPECT_LT(worst, 1e-4 * 0.6) << "1e-4 of the skirt's ~0.6 m diagonal";
}

TEST(TrainingLearns, ResumedRunContinuesExactly) {
  const std::string root = pleat_test::temp_dir("training_resume");
  const std::string data = write_data(root);
  Trainer straight(config(data, root + "/straight", 4));
  straight.run();
  {
    Trainer first(config(data, root + "/resumed", 4));
    first.run(2);  // interrupted after two epochs
  }
  Trainer second(config(data, root + "/resumed", 4));
  EXPECT_EQ(second.epoch(), 2) << "resumed from the checkpoint";
  second.run();
  const auto a = straight.network()->parameters(), b = second.network()->parameters();
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(torch::equal(a[i], b[i])) << "parameter " << i;
}
