// `pleat train` and `pleat export` as a user runs them: a config file, a
// data set on disk, a model file out; bad configurations named.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "runtime/model_file.h"
#include "support/synthetic_sequence.h"
#include "support/test_support.h"

namespace {

std::string cli() {
  const char* v = std::getenv("PLEAT_CLI");
  return v ? v : "";
}

int lines(const std::string& path) {
  std::ifstream in(path);
  int n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

}  // namespace

TEST(TrainingCli, TrainWritesAModelAndExportRewritesIt) {
  const std::string root = pleat_test::temp_dir("training_cli");
  const std::string data = pleat_test::write_skirt_walk(root);
  std::ofstream(root + "/schedule.json") << R"({"phases": [{"name": "supervised",
      "weights": {"vertex": 100, "k_mid": 2, "k_high": 1.5, "edge": 15}}]})";
  std::ofstream(root + "/config.json") << R"({"train": ["skirt_walk"], "validation": ["skirt_walk"],
      "schedule": "schedule.json", "output": "run", "epochs": 3, "batch_frames": 8, "progress": false,
      "model": {"code_width": 16, "body_widths": [16], "garment_widths": [16, 16], "gru_layers": 1,
                "blend_widths": [16, 3], "refinement_widths": [16, 3]}})";
  std::string text;
  ASSERT_EQ(pleat_test::run_command(cli() + " train " + root + "/config.json 2>&1", &text), 0) << text;
  EXPECT_NE(text.find("trained 3 epochs"), std::string::npos) << text;
  EXPECT_EQ(lines(root + "/run/log.csv"), 4) << "a header and one row per epoch";
  const auto model = pleat::runtime::load_model_file(root + "/run/model.pleat");
  EXPECT_EQ(model->training.epochs, 3);
  EXPECT_EQ(model->code_width(), 16);

  // Two more epochs resume the run; export writes the latest checkpoint.
  ASSERT_EQ(pleat_test::run_command(cli() + " train " + root + "/config.json --epochs 5 2>&1", &text), 0)
      << text;
  EXPECT_NE(text.find("resuming"), std::string::npos) << text;
  EXPECT_EQ(lines(root + "/run/log.csv"), 6);
  ASSERT_EQ(pleat_test::run_command(cli() + " export " + root + "/config.json -o " + root + "/out.pleat 2>&1",
                                    &text),
            0)
      << text;
  EXPECT_EQ(pleat::runtime::load_model_file(root + "/out.pleat")->training.epochs, 5);

  std::ofstream(root + "/bad.json")
      << R"({"train": ["skirt_walk"], "schedule": "schedule.json", "output": "x",
      "model": {"variant": "transformer"}})";
  EXPECT_EQ(pleat_test::run_command(cli() + " train " + root + "/bad.json 2>&1", &text), 1);
  EXPECT_NE(text.find("bad.json"), std::string::npos) << text;
  EXPECT_NE(text.find("model.variant"), std::string::npos) << text;
}

TEST(TrainingCli, AblationTrainsTheFourConfigurationsAndWritesTheTable) {
  const std::string root = pleat_test::temp_dir("training_ablation");
  pleat_test::write_skirt_walk(root);
  std::ofstream(root + "/schedule.json") << R"({"phases": [{"name": "supervised",
      "weights": {"vertex": 100, "k_mid": 2, "k_high": 1.5, "edge": 15}}]})";
  std::ofstream(root + "/config.json") << R"({"train": ["skirt_walk"], "validation": ["skirt_walk"],
      "schedule": "schedule.json", "output": "ablation", "epochs": 1, "batch_frames": 16, "progress": false,
      "plot": false, "model": {"code_width": 8, "body_widths": [8], "garment_widths": [8, 8], "gru_layers": 1,
                "blend_widths": [8, 3], "refinement_widths": [8, 3]}})";
  std::string text;
  ASSERT_EQ(pleat_test::run_command(cli() + " ablation " + root + "/config.json 2>&1", &text), 0) << text;
  for (const char* run : {"gat_freqdiv", "lgat_freqdiv", "flexigat_plain", "flexigat_freqdiv"}) {
    EXPECT_NE(text.find(run), std::string::npos) << text;
    EXPECT_TRUE(std::filesystem::exists(root + "/ablation/" + run + "/checkpoint.json")) << run;
  }
  EXPECT_EQ(lines(root + "/ablation/ablation.md"), 6) << "header, rule and four rows";
  EXPECT_EQ(lines(root + "/ablation/ablation.csv"), 5);
}
