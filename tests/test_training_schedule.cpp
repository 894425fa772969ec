// The progressive schedule: phase changes and accumulated weights worked out
// by hand, checkpoint round trips, refused files, and the shipped schedules
// (the demo's must be the paper's phases and weights with shorter advances).
#include <gtest/gtest.h>

#include <utility>

#include "capi/pleat.h"
#include "core/error.h"
#include "schedule.h"
#include "support/test_support.h"

using namespace pleat::training;

namespace {

const char* kThreePhases = R"({"phases": [
  {"name": "a", "weights": {"vertex": 100, "edge": 10, "curvature": 4}, "advance": {"e_verts_below_cm": 5}},
  {"name": "b", "weights": {"normal": 50}, "advance": {"plateau": {"epochs": 2, "improvement": 0.1}}},
  {"name": "c", "scale_supervised": 0.1, "freeze_encoders": true, "weights": {"collision": 2},
   "advance": {"loss_below": 0.5, "epochs": 3}},
  {"name": "d", "scale_supervised": 0.5, "weights": {"stretch": 5}}]})";

std::string schedule_file(const char* name) {
  return pleat_test::source_dir() + "/data/schedules/" + name;
}

void expect_refused(const std::string& json, const std::string& fragment) {
  try {
    parse_schedule(json, "s.json");
    ADD_FAILURE() << "accepted: " << json;
  } catch (const pleat::Error& e) {
    EXPECT_EQ(e.status(), PLEAT_ERROR_FORMAT);
    EXPECT_NE(std::string(e.what()).find("s.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(TrainingSchedule, AdvancesOnEachConditionAndScalesTheSupervisedWeights) {
  ScheduleState s(parse_schedule(kThreePhases, "three.json"));
  EXPECT_EQ(s.phase().name, "a");
  EXPECT_FALSE(s.end_epoch(6.0, 9.0));
  EXPECT_TRUE(s.end_epoch(4.9, 9.0));  // below 5 cm
  EXPECT_EQ(s.phase().name, "b");
  EXPECT_DOUBLE_EQ(s.weights().at("normal"), 50);

  // Plateau over 2 epochs at 10%: 4.0 -> 3.5 -> 3.3 is 17.5% (stay), then
  // 3.5 -> 3.3 -> 3.2 is 8.6% (advance).
  EXPECT_FALSE(s.end_epoch(4.0, 9.0));
  EXPECT_FALSE(s.end_epoch(3.5, 9.0));
  EXPECT_FALSE(s.end_epoch(3.3, 9.0));
  EXPECT_TRUE(s.end_epoch(3.2, 9.0));
  EXPECT_EQ(s.phase().name, "c");
  EXPECT_TRUE(s.encoders_frozen());
  EXPECT_DOUBLE_EQ(s.weights().at("vertex"), 10);
  EXPECT_DOUBLE_EQ(s.weights().at("edge"), 1);
  EXPECT_DOUBLE_EQ(s.weights().at("curvature"), 0.4);
  EXPECT_DOUBLE_EQ(s.weights().at("normal"), 5);
  EXPECT_DOUBLE_EQ(s.weights().at("collision"), 2);

  // Either condition: the epoch count here, since the loss stays above 0.5.
  EXPECT_FALSE(s.end_epoch(3.0, 2.0));
  EXPECT_FALSE(s.end_epoch(3.0, 2.0));
  EXPECT_TRUE(s.end_epoch(3.0, 2.0));
  EXPECT_EQ(s.phase().name, "d");
  EXPECT_TRUE(s.encoders_frozen());  // freezing is never undone
  EXPECT_DOUBLE_EQ(s.weights().at("vertex"), 5);
  EXPECT_DOUBLE_EQ(s.weights().at("normal"), 2.5);
  EXPECT_DOUBLE_EQ(s.weights().at("collision"), 2);  // not a supervised weight
  EXPECT_DOUBLE_EQ(s.weights().at("stretch"), 5);
  EXPECT_FALSE(s.end_epoch(0.1, 0.0));  // the last phase never ends
}

TEST(TrainingSchedule, LossBelowAdvances) {
  ScheduleState s(parse_schedule(kThreePhases, "three.json"));
  s.end_epoch(1.0, 9.0);
  for (double e : {3.0, 2.9, 2.9}) s.end_epoch(e, 9.0);  // a plateau
  ASSERT_EQ(s.phase().name, "c");
  EXPECT_TRUE(s.end_epoch(3.0, 0.4));
}

TEST(TrainingSchedule, RestoreContinuesWhereTheSavedStateWas) {
  const Schedule schedule = parse_schedule(kThreePhases, "three.json");
  ScheduleState a(schedule);
  a.end_epoch(4.0, 9.0);
  a.end_epoch(4.0, 9.0);
  a.end_epoch(3.9, 9.0);
  ScheduleState b(schedule);
  b.restore(a.save());
  EXPECT_EQ(b.phase_index(), 1u);
  EXPECT_EQ(b.weights(), a.weights());
  // Both have the plateau history 4.0, 3.9: the next epoch decides the same.
  EXPECT_EQ(a.end_epoch(3.8, 9.0), b.end_epoch(3.8, 9.0));
  EXPECT_EQ(b.phase().name, "c");
}

TEST(TrainingSchedule, RefusesBadFilesNamingFileAndPhase) {
  expect_refused("[]", "non-empty 'phases'");
  expect_refused(R"({"phases": [{"name": "x", "colour": 1}]})", "unknown key 'colour'");
  expect_refused(R"({"phases": [{"name": "x", "weights": {"wind": 1}}]})", "unknown loss 'wind'");
  expect_refused(R"({"phases": [{"name": "x", "weights": {"vertex": -1}}]})", "weight of 'vertex'");
  expect_refused(R"({"phases": [{"advance": {"plateau": {"epochs": 0, "improvement": 0.1}}}]})",
                 "phase 0: plateau epochs");
  expect_refused(R"({"phases": [{}, {"advance": {"soon": true}}]})", "phase 1: unknown advance condition");
}

TEST(TrainingSchedule, DemoScheduleIsThePapersWithShorterAdvancesCurvatureSmoothnessAndMidBand) {
  const Schedule paper = read_schedule(schedule_file("paper.json"));
  const Schedule demo = read_schedule(schedule_file("demo.json"));
  ASSERT_EQ(paper.phases.size(), 5u);
  ASSERT_EQ(demo.phases.size(), paper.phases.size());
  for (size_t i = 0; i < paper.phases.size(); ++i) {
    const Phase &p = paper.phases[i], &d = demo.phases[i];
    EXPECT_EQ(d.name, p.name);
    // The paper's weights, plus pleat's curvature term (decision 0005),
    // skinning smoothness (decision 0006) and offset smoothness (decisions
    // 0007, 0009) from the first phase on, and a stronger mid band (decision
    // 0009).
    LossWeights expected = p.weights;
    if (i == 0) {
      EXPECT_EQ(p.weights.at("k_mid"), 2) << "the paper's mid-band weight";
      expected["k_mid"] = 8, expected["curvature"] = 25, expected["skinning_smoothness"] = 50,
      expected["offset_smoothness"] = 10;
    }
    EXPECT_EQ(d.weights, expected) << p.name;
    EXPECT_EQ(d.scale_supervised, p.scale_supervised) << p.name;
    EXPECT_EQ(d.freeze_encoders, p.freeze_encoders) << p.name;
    EXPECT_EQ(d.e_verts_below_cm, p.e_verts_below_cm) << p.name;
    EXPECT_EQ(d.plateau_improvement, p.plateau_improvement) << p.name;
    EXPECT_EQ(d.loss_below, p.loss_below) << p.name;
    EXPECT_LE(d.plateau_epochs, p.plateau_epochs) << p.name;
    if (i + 1 < paper.phases.size()) {  // every phase but the last ends within a few epochs
      EXPECT_TRUE((d.epochs > 0 && d.epochs <= 4) || (d.plateau_epochs > 0 && d.plateau_epochs <= 2))
          << p.name;
    }
  }
}

// The per-asset schedule (decision 0010) fits the data first, then adds the
// paper's normal, curvature, collision and self-collision terms while the data
// term keeps its full weight: no phase scales the supervised terms down or
// freezes the encoders, and no phase has a term whose minimum is the body's
// own skinning (skinning or offset smoothness). The supervised phase ends on a
// plateau or after a fixed count, so the last phase trains at a learning rate
// that still moves the weights.
TEST(TrainingSchedule, PerAssetScheduleHasNoTermWhoseMinimumIsLbs) {
  const Schedule s = read_schedule(schedule_file("per_asset.json"));
  ASSERT_GE(s.phases.size(), 2u);
  LossWeights seen;
  for (const Phase& p : s.phases) {
    for (const auto& [name, weight] : p.weights) seen[name] = weight;
    EXPECT_FALSE(p.weights.count("skinning_smoothness")) << p.name;
    EXPECT_FALSE(p.weights.count("offset_smoothness")) << p.name;
    EXPECT_EQ(p.scale_supervised, 1.0) << p.name;
    EXPECT_FALSE(p.freeze_encoders) << p.name;
  }
  const Phase& first = s.phases.front();
  EXPECT_EQ(first.weights.at("vertex"), 100);
  EXPECT_GT(first.weights.at("k_mid"), 0) << "frequency-divided supervision";
  EXPECT_GT(first.plateau_epochs, 0);
  EXPECT_GT(first.epochs, 0);
  for (const char* term : {"normal", "curvature", "collision", "self_collision"})
    EXPECT_GT(seen[term], 0) << term;
  EXPECT_EQ(seen.at("vertex"), 100) << "the data term keeps its weight to the end";
}

// The mid-band experiments (decisions 0016, 0019, 0021) compare against the
// per-asset schedule on the premise that only k_mid differs: every other
// weight, every phase and every advance rule must match it.
TEST(TrainingSchedule, MidBandVariantsChangeOnlyTheMidBandWeight) {
  const Schedule base = read_schedule(schedule_file("per_asset.json"));
  for (const auto& [file, k_mid] : {std::pair<const char*, double>{"per_asset_kmid16.json", 16},
                                    std::pair<const char*, double>{"per_asset_kmid32.json", 32}}) {
    const Schedule s = read_schedule(schedule_file(file));
    ASSERT_EQ(s.phases.size(), base.phases.size()) << file;
    for (size_t i = 0; i < s.phases.size(); ++i) {
      const Phase& p = s.phases[i];
      const Phase& b = base.phases[i];
      LossWeights expected = b.weights;
      if (expected.count("k_mid")) expected["k_mid"] = k_mid;
      EXPECT_EQ(p.weights, expected) << file << " phase " << i;
      EXPECT_EQ(p.name, b.name) << file;
      EXPECT_EQ(p.epochs, b.epochs) << file;
      EXPECT_EQ(p.plateau_epochs, b.plateau_epochs) << file;
      EXPECT_EQ(p.plateau_improvement, b.plateau_improvement) << file;
    }
    EXPECT_EQ(s.phases.front().weights.at("k_mid"), k_mid) << file;
  }
}
