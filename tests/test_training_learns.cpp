// The trainer end to end on a small synthetic data set written in the
// sequence format: the MakeHuman body walks (the CMU fixture clip); the
// "simulated" skirt is the body's own skinning of the skirt pushed 2 cm
// outwards, which the untrained model does not know. Training must cut
// E_verts by at least 10x; a run resumed from its checkpoint must continue
// exactly as an uninterrupted one; the exported model must reproduce the
// trainer in the runtime.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "evaluation.h"
#include "runtime/model_file.h"
#include "support/expect_error.h"
#include "support/synthetic_sequence.h"
#include "support/test_support.h"
#include "trainer.h"

using namespace pleat;
using namespace pleat::training;

namespace {

TrainerConfig config(const std::string& data, const std::string& output, int64_t epochs) {
  TrainerConfig c;
  c.train = {data};
  c.validation = {data};
  c.schedule = parse_schedule(R"({"phases": [{"name": "supervised",
      "weights": {"vertex": 100, "k_mid": 2, "k_high": 1.5, "edge": 15, "curvature": 5}}]})",
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
  const std::string data = pleat_test::write_skirt_walk(root);
  Trainer trainer(config(data, root + "/run", 60));
  const double initial = trainer.validate(trainer.training_data()).e_verts_cm;
  const EpochResult last = trainer.run();
  std::printf("E_verts %.3f cm -> %.3f cm in %lld epochs, %.1f training frames/s\n", initial,
              last.validation.e_verts_cm, static_cast<long long>(last.epoch), last.frames_per_second);
  EXPECT_GT(initial, 1.0) << "the untrained model does not know the offset";
  EXPECT_LT(last.validation.e_verts_cm, initial / 10.0);
  EXPECT_TRUE(std::filesystem::exists(root + "/run/log.csv"));
  {
    // One row per epoch and term, each term with a loss and a gradient norm.
    std::ifstream terms(root + "/run/terms.csv");
    std::string line;
    std::getline(terms, line);
    EXPECT_EQ(line, "epoch,term,loss,gradient_norm");
    std::map<std::string, int> rows;
    while (std::getline(terms, line)) {
      std::vector<std::string> f;
      std::stringstream row(line);
      for (std::string cell; std::getline(row, cell, ',');) f.push_back(cell);
      ASSERT_EQ(f.size(), 4u) << line;
      ++rows[f[1]];
      EXPECT_GT(std::atof(f[2].c_str()), 0.0) << line;
      EXPECT_GT(std::atof(f[3].c_str()), 0.0) << line;
    }
    EXPECT_EQ(rows, (std::map<std::string, int>{{"curvature", 60}, {"edge", 60}, {"vertex", 60}}));
  }
  {
    std::ifstream png(root + "/run/curves.png", std::ios::binary);
    char magic[8] = {};
    png.read(magic, 8);
    EXPECT_EQ(std::string(magic + 1, 3), "PNG") << "the curves are plotted";
  }

  // The export (the kept epoch) reproduces the trainer's network in the runtime.
  const std::shared_ptr<runtime::Model> model = trainer.export_model();
  runtime::save_model(*model, root + "/run/model.pleat");
  const auto loaded = runtime::load_model_file(root + "/run/model.pleat");
  EXPECT_EQ(loaded->training.optimizer, "adamax");
  EXPECT_EQ(loaded->training.epochs, trainer.best_epoch());
  EXPECT_LT(loaded->training.metrics.front().value, initial / 10.0);
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
  Network kept(*loaded);
  const torch::Tensor trained =
      kept->forward(bound, s.poses(), {20}, runtime::Stage::refinement).positions.contiguous();
  double worst = 0;
  for (int i = 0; i < n * 3; ++i)
    worst = std::max(worst, double(std::abs(trained.data_ptr<float>()[i] - runtime_positions[i])));
  EXPECT_LT(worst, 1e-4 * 0.6) << "1e-4 of the skirt's ~0.6 m diagonal";
}

TEST(TrainingLearns, ResumedRunContinuesExactly) {
  const std::string root = pleat_test::temp_dir("training_resume");
  const std::string data = pleat_test::write_skirt_walk(root);
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

  TrainerConfig strided = config(data, root + "/resumed", 4);
  strided.model.body_vertex_stride = 2;
  pleat_test::expect_error([&] { Trainer third(strided); }, PLEAT_ERROR_FORMAT,
                           "was trained with body_vertex_stride 1, the config asks for 2");
  TrainerConfig filtered = config(data, root + "/resumed", 4);
  filtered.model.offset_filter_length = 0.25f;
  pleat_test::expect_error([&] { Trainer fourth(filtered); }, PLEAT_ERROR_FORMAT,
                           "was trained with offset_filter_length 0, the config asks for 0.25");
}

TEST(TrainingLearns, EpochBatchesMixSequencesAndCoverEveryFrameOnce) {
  const std::string root = pleat_test::temp_dir("training_batches");
  const std::string a = pleat_test::write_skirt_walk(root + "/a"),
                    b = pleat_test::write_skirt_walk(root + "/b");
  const Dataset data({a, b});
  ASSERT_EQ(data.sequences().size(), 2u);
  EXPECT_EQ(data.sequences()[0].garment, data.sequences()[1].garment) << "one garment name, prepared once";
  std::mt19937_64 rng(5);
  const auto batches = data.epoch(16, 0, rng);
  std::set<std::pair<size_t, int64_t>> seen;
  size_t mixed = 0;
  for (const Dataset::Batch& batch : batches) {
    size_t frames = 0;
    for (const Dataset::Part& part : batch) {
      frames += part.frames.size();
      for (int64_t f : part.frames) EXPECT_TRUE(seen.insert({part.sequence, f}).second) << "frame twice";
    }
    EXPECT_LE(frames, 16u);
    mixed += batch.size() > 1;
  }
  EXPECT_EQ(seen.size(), size_t(data.frame_count()));
  EXPECT_GT(mixed, 0u) << "batches draw frames from both sequences";

  // One sequence per batch: every frame still once, and no batch mixes.
  seen.clear();
  const auto single = data.epoch(16, 1, rng);
  for (const Dataset::Batch& batch : single) {
    EXPECT_EQ(batch.size(), 1u);
    EXPECT_LE(batch[0].frames.size(), 16u);
    for (int64_t f : batch[0].frames)
      EXPECT_TRUE(seen.insert({batch[0].sequence, f}).second) << "frame twice";
  }
  EXPECT_EQ(seen.size(), size_t(data.frame_count()));
  size_t expected = 0;
  for (const auto& sequence : data.sequences()) expected += size_t(sequence.frame_count() + 15) / 16;
  EXPECT_EQ(single.size(), expected) << "full batches and one short one per sequence";
}

// The LBS baseline skins the rest skirt with the nearest body weights: the
// data's skirt is the same skinning of the skirt pushed 2 cm outwards, so
// the baseline's error is about those 2 cm (blending shortens it a little).
TEST(TrainingLearns, LbsBaselineMissesThePush) {
  const std::string root = pleat_test::temp_dir("training_baseline");
  const Dataset data({pleat_test::write_skirt_walk(root)});
  const MetricsResult m = lbs_baseline(data);
  EXPECT_EQ(m.frame_count, 31u);
  EXPECT_GT(m.e_verts_cm, 1.8);
  EXPECT_LT(m.e_verts_cm, 2.05);
}

TEST(TrainingLearns, WorstRatioIsTheLargestFractionOfTheBaseline) {
  MetricsResult lbs, model;
  lbs.e_verts_cm = 2.0, model.e_verts_cm = 1.0;                          // 0.5
  lbs.e_curv = 400.0, model.e_curv = 600.0;                              // 1.5: the worst
  lbs.e_edge_percent = 10.0, model.e_edge_percent = 12.0;                // 1.2
  lbs.self_collision_percent = 0.0, model.self_collision_percent = 3.0;  // left out: LBS has none
  EXPECT_DOUBLE_EQ(worst_ratio(model, lbs), 1.5);
  model.e_curv = 300.0;
  EXPECT_DOUBLE_EQ(worst_ratio(model, lbs), 1.2);
}

// With validation data the trainer keeps the epoch with the lowest
// validation E_verts: recomputed here from log.csv, and the export (also
// after a resume, from best.pt) carries that epoch's validation metrics.
TEST(TrainingLearns, KeepsTheEpochWithTheLowestValidationError) {
  const std::string root = pleat_test::temp_dir("training_best");
  const std::string data = pleat_test::write_skirt_walk(root);
  TrainerConfig c = config(data, root + "/run", 5);
  // Three supervised epochs, then two that only pull the skirt down: the
  // last epoch is not the one to keep.
  c.schedule = parse_schedule(R"({"phases": [
      {"name": "supervised", "weights": {"vertex": 100, "k_mid": 2, "k_high": 1.5, "edge": 15},
       "advance": {"epochs": 3}},
      {"name": "sag", "scale_supervised": 0, "weights": {"gravity": 1000}}]})",
                              "test");
  int64_t expected = 0;
  std::vector<MetricsResult> logged;
  {
    Trainer trainer(c);
    trainer.run();
    const MetricsResult& lbs = trainer.validation_baseline();
    EXPECT_GT(lbs.e_verts_cm, 1.0);
    std::ifstream log(root + "/run/log.csv");
    std::string line;
    std::getline(log, line);  // header
    while (std::getline(log, line)) {
      std::vector<double> f;
      std::stringstream row(line);
      for (std::string cell; std::getline(row, cell, ',');) f.push_back(std::atof(cell.c_str()));
      MetricsResult m;
      m.e_verts_cm = f[5], m.e_vnorm_deg = f[6], m.e_fnorm_deg = f[7], m.e_edge_percent = f[8];
      m.e_curv = f[9], m.e_low_cm = f[10], m.e_mid_cm = f[11], m.e_high_cm = f[12];
      m.self_collision_percent = f[13];
      logged.push_back(m);
      EXPECT_NEAR(f[17], lbs.e_verts_cm, 1e-4 * lbs.e_verts_cm) << "the LBS column";
      EXPECT_NEAR(f[16], trainer.training_baseline().e_verts_cm, 1e-4 * lbs.e_verts_cm);
      if (expected == 0 || m.e_verts_cm < logged[static_cast<size_t>(expected - 1)].e_verts_cm)
        expected = static_cast<int64_t>(logged.size());
    }
    ASSERT_EQ(logged.size(), 5u);
    EXPECT_LE(expected, 3) << "an epoch before the sag is kept";
    EXPECT_EQ(trainer.best_epoch(), expected);
  }
  Trainer resumed(c);  // nothing left to train: export from the checkpoint and best.pt
  EXPECT_EQ(resumed.epoch(), 5);
  EXPECT_EQ(resumed.best_epoch(), expected);
  const std::shared_ptr<runtime::Model> model = resumed.export_model();
  EXPECT_EQ(model->training.epochs, expected);
  const MetricsResult& kept = logged[static_cast<size_t>(expected - 1)];
  EXPECT_NEAR(model->training.metrics[0].value, kept.e_verts_cm, 1e-4 * kept.e_verts_cm);
  EXPECT_NEAR(model->training.metrics[4].value, kept.e_curv, 1e-4 * kept.e_curv);
  // The exported weights are the kept epoch's: the runtime, skinning with
  // every joint as the trainer does, scores them as the trainer did after
  // that epoch (float rounding apart).
  runtime::InstanceOptions exact;
  exact.top_k = model->joint_count();
  const MetricsResult rescored =
      model_metrics(resumed.training_data(), model, runtime::Stage::refinement, exact);
  EXPECT_NEAR(rescored.e_verts_cm, kept.e_verts_cm, 1e-3 * kept.e_verts_cm);
  EXPECT_NEAR(rescored.e_curv, kept.e_curv, 1e-3 * kept.e_curv);
}
