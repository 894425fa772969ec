// `pleat train` and `pleat export` as a user runs them: a config file, a
// data set on disk, a model file out; bad configurations named.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "io/point_cache.h"
#include "io/sequence.h"
#include "runtime/model_file.h"
#include "runtime/model_init.h"
#include "support/synthetic_sequence.h"
#include "support/test_support.h"
#include "trainer.h"

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

// The epoch the run keeps (checkpoint.json), and the one the model file says it holds.
void expect_kept_epoch(const std::string& run, const std::string& model_file, int64_t epochs) {
  std::ifstream in(run + "/checkpoint.json");
  const nlohmann::json checkpoint = nlohmann::json::parse(in);
  const int64_t kept = checkpoint.at("best_epoch").get<int64_t>();
  EXPECT_GE(kept, 1);
  EXPECT_LE(kept, epochs);
  const auto model = pleat::runtime::load_model_file(model_file);
  EXPECT_EQ(model->training.epochs, kept);
  EXPECT_NE(
      model->training.schedule.find("kept epoch " + std::to_string(kept) + " of " + std::to_string(epochs)),
      std::string::npos)
      << model->training.schedule;
}

// A one-epoch run of a tiny model on `root`/set (whose splits.json the
// caller writes), as `pleat train` leaves it: root/run/model.pleat; what it
// printed goes to `output`.
void train_tiny_model(const std::string& root, std::string* output = nullptr) {
  std::ofstream(root + "/schedule.json")
      << R"({"phases": [{"name": "supervised", "weights": {"vertex": 100}}]})";
  std::ofstream(root + "/config.json") << R"({"dataset": "set", "schedule": "schedule.json", "output": "run",
      "epochs": 1, "batch_frames": 16, "progress": false, "plot": false,
      "model": {"code_width": 8, "body_widths": [8], "garment_widths": [8, 8], "gru_layers": 1,
                "blend_widths": [8, 3], "refinement_widths": [8, 3]}})";
  std::string text;
  ASSERT_EQ(pleat_test::run_command(cli() + " train " + root + "/config.json 2>&1", &text), 0) << text;
  if (output) *output = text;
}

}  // namespace

TEST(TrainingCli, TrainWritesAModelAndExportRewritesIt) {
  const std::string root = pleat_test::temp_dir("training_cli");
  const std::string data = pleat_test::write_skirt_walk(root);
  std::ofstream(root + "/schedule.json") << R"({"phases": [{"name": "supervised",
      "weights": {"vertex": 100, "k_mid": 2, "k_high": 1.5, "edge": 15, "offset_smoothness": 1}}]})";
  std::ofstream(root + "/config.json") << R"({"train": ["skirt_walk"], "validation": ["skirt_walk"],
      "schedule": "schedule.json", "output": "run", "epochs": 3, "batch_frames": 8, "progress": false,
      "model": {"code_width": 16, "body_widths": [16], "garment_widths": [16, 16], "gru_layers": 1,
                "blend_widths": [16, 3], "refinement_widths": [16, 3], "default_top_k": 6,
                "refinement_features": ["velocity", "normal", "posed_joint_distances", "fused_code"]}})";
  std::string text;
  ASSERT_EQ(pleat_test::run_command(cli() + " train " + root + "/config.json 2>&1", &text), 0) << text;
  EXPECT_NE(text.find("trained 3 epochs"), std::string::npos) << text;
  EXPECT_NE(text.find("validation E_verts"), std::string::npos) << text;
  // A misspelt option is refused, not ignored; --help is usage on stdout.
  EXPECT_EQ(pleat_test::run_command(cli() + " train " + root + "/config.json --epoch 5 2>&1", &text), 2);
  EXPECT_NE(text.find("unknown or incomplete option '--epoch'"), std::string::npos) << text;
  EXPECT_EQ(pleat_test::run_command(cli() + " train --help 2>/dev/null", &text), 0);
  EXPECT_NE(text.find("usage: pleat-train train config.json"), std::string::npos) << text;
  EXPECT_EQ(lines(root + "/run/log.csv"), 4) << "a header and one row per epoch";
  const auto trained = pleat::runtime::load_model_file(root + "/run/model.pleat");
  EXPECT_EQ(trained->code_width(), 16);
  EXPECT_EQ(trained->default_top_k, 6);
  EXPECT_TRUE(pleat::runtime::refinement_reads_code(*trained));
  expect_kept_epoch(root + "/run", root + "/run/model.pleat", 3);

  // Two more epochs resume the run; export writes the kept epoch of all five.
  ASSERT_EQ(pleat_test::run_command(cli() + " train " + root + "/config.json --epochs 5 2>&1", &text), 0)
      << text;
  EXPECT_NE(text.find("resuming"), std::string::npos) << text;
  EXPECT_EQ(lines(root + "/run/log.csv"), 6);
  ASSERT_EQ(pleat_test::run_command(cli() + " export " + root + "/config.json -o " + root + "/out.pleat 2>&1",
                                    &text),
            0)
      << text;
  expect_kept_epoch(root + "/run", root + "/out.pleat", 5);

  std::ofstream(root + "/bad.json")
      << R"({"train": ["skirt_walk"], "schedule": "schedule.json", "output": "x",
      "model": {"variant": "transformer"}})";
  EXPECT_EQ(pleat_test::run_command(cli() + " train " + root + "/bad.json 2>&1", &text), 1);
  EXPECT_NE(text.find("bad.json"), std::string::npos) << text;
  EXPECT_NE(text.find("model.variant"), std::string::npos) << text;
  std::ofstream(root + "/bad.json")
      << R"({"train": ["skirt_walk"], "schedule": "schedule.json", "output": "x",
      "model": {"refinement_features": ["velocity", "swing"]}})";
  EXPECT_EQ(pleat_test::run_command(cli() + " train " + root + "/bad.json 2>&1", &text), 1);
  EXPECT_NE(text.find("model.refinement_features has unknown feature 'swing'"), std::string::npos) << text;

  // The run's checkpoint has the code's columns: a config without them cannot resume it.
  std::ifstream in(root + "/config.json");
  std::string config((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  config.replace(config.find(", \"fused_code\""), 14, "");
  std::ofstream(root + "/blind.json") << config;
  EXPECT_NE(pleat_test::run_command(cli() + " train " + root + "/blind.json --epochs 6 2>&1", &text), 0);
  EXPECT_NE(text.find("was made for another architecture (tensor"), std::string::npos) << text;
}

TEST(TrainingCli, AblationTrainsTheFourConfigurationsAndWritesTheTable) {
  const std::string root = pleat_test::temp_dir("training_ablation");
  pleat_test::write_skirt_walk(root);
  std::ofstream(root + "/schedule.json") << R"({"phases": [{"name": "supervised",
      "weights": {"vertex": 100, "k_mid": 2, "k_high": 1.5, "edge": 15, "offset_smoothness": 1}}]})";
  std::ofstream(root + "/config.json") << R"({"train": ["skirt_walk"], "validation": ["skirt_walk"],
      "schedule": "schedule.json", "output": "ablation", "epochs": 1, "batch_frames": 16, "progress": false,
      "plot": false, "model": {"code_width": 8, "body_widths": [8], "garment_widths": [8, 8], "gru_layers": 1,
                "blend_widths": [8, 3], "refinement_widths": [8, 3]}})";
  std::string text;
  // One run alone (a second core would take another): no table yet.
  ASSERT_EQ(
      pleat_test::run_command(cli() + " ablation " + root + "/config.json --only lgat_freqdiv 2>&1", &text),
      0)
      << text;
  EXPECT_TRUE(std::filesystem::exists(root + "/ablation/lgat_freqdiv/checkpoint.json"));
  EXPECT_FALSE(std::filesystem::exists(root + "/ablation/gat_freqdiv"));
  EXPECT_FALSE(std::filesystem::exists(root + "/ablation/ablation.md"));
  EXPECT_NE(pleat_test::run_command(cli() + " ablation " + root + "/config.json --only gcn 2>&1", &text), 0);
  EXPECT_NE(text.find("ablation has no run 'gcn'"), std::string::npos) << text;
  ASSERT_EQ(pleat_test::run_command(cli() + " ablation " + root + "/config.json 2>&1", &text), 0) << text;
  EXPECT_EQ(lines(root + "/ablation/lgat_freqdiv/log.csv"), 2) << "lgat_freqdiv is not trained again";
  for (const char* run : {"gat_freqdiv", "lgat_freqdiv", "flexigat_plain", "flexigat_freqdiv"}) {
    EXPECT_NE(text.find(run), std::string::npos) << text;
    EXPECT_TRUE(std::filesystem::exists(root + "/ablation/" + run + "/checkpoint.json")) << run;
    EXPECT_EQ(pleat::runtime::load_model_file(root + "/ablation/" + run + "/model.pleat")
                  ->garment_encoder.layers[0]
                  .variant,
              std::string(run).rfind("gat_", 0) == 0    ? pleat::nn::AttentionVariant::gat
              : std::string(run).rfind("lgat_", 0) == 0 ? pleat::nn::AttentionVariant::lgat
                                                        : pleat::nn::AttentionVariant::flexigat)
        << run;
  }
  EXPECT_EQ(lines(root + "/ablation/ablation.md"), 6) << "header, rule and four rows";
  EXPECT_EQ(lines(root + "/ablation/ablation.csv"), 5);
}

// A data set as pleat datagen leaves it (splits.json, with a twin of the
// sequence), named by "dataset"; `pleat-train evaluate` scores LBS, the
// noise floor and a model on every split, side by side.
TEST(TrainingCli, EvaluateScoresEverySplitOfADataSet) {
  const std::string root = pleat_test::temp_dir("training_evaluate");
  pleat_test::write_skirt_walk(root + "/set");
  // The twin's skirt sits 5 mm further out: the noise floor is those 5 mm
  // (a little less where blended skinning shortens them).
  pleat_test::write_skirt_walk(root + "/set", 0.025, "skirt_walk.twin");
  std::ofstream(root + "/set/splits.json") << R"({"train": ["skirt_walk"], "validation": [],
      "test": ["skirt_walk"], "twins": {"skirt_walk": "skirt_walk.twin"}})";
  std::string text, baseline;
  ASSERT_NO_FATAL_FAILURE(train_tiny_model(root, &text));
  // Without a validation split the run keeps its last epoch and says so (no E_verts of 0).
  EXPECT_NE(text.find("epoch 1, the last (no validation split to choose by)"), std::string::npos) << text;
  const std::string trainer = std::filesystem::path(cli()).parent_path().string() + "/pleat-train";
  ASSERT_EQ(pleat_test::run_command(trainer + " evaluate " + root + "/config.json --model " + root +
                                        "/run/model.pleat -o " + root + "/report.md 2>&1",
                                    &text),
            0)
      << text;
  EXPECT_NE(text.find("### Training split: 1 sequences"), std::string::npos) << text;
  EXPECT_EQ(text.find("### Validation split"), std::string::npos) << "the set has no validation sequence";
  EXPECT_NE(text.find("### Test split: 1 sequences"), std::string::npos) << text;
  EXPECT_NE(text.find("| model |"), std::string::npos) << "a row per model, named by its file" << text;
  EXPECT_EQ(text.find("held-out garments"), std::string::npos) << "no held-out garment in this set";
  EXPECT_EQ(lines(root + "/report.md"), 21) << "per split: blank, title, blank, header, rule, LBS, noise "
                                               "floor, the model; blank, the preview; blank, "
                                               "two summaries";
  EXPECT_NE(text.find("![model (blue) and the simulation (orange) on skirt_walk, frames 0, 15 and 30]"
                      "(report_preview.png)"),
            std::string::npos)
      << text;
  std::ifstream png(root + "/report_preview.png", std::ios::binary);
  char magic[4] = {};
  png.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG") << "the preview beside the report";
  const std::string floor_row = "| noise floor (twin simulations, 1 of 1 sequences) | ";
  ASSERT_NE(text.find(floor_row), std::string::npos) << text;
  const double floor = std::stod(text.substr(text.find(floor_row) + floor_row.size()));
  EXPECT_GT(floor, 0.4);
  EXPECT_LE(floor, 0.5);
  // The summary lines, one per model and split, carry the same numbers.
  const std::string row = "| LBS (nearest body weights) | ";
  ASSERT_NE(text.find(row), std::string::npos) << text;
  const double lbs = std::stod(text.substr(text.find(row) + row.size()));
  const size_t summary = text.find("summary: model=model split=train e_verts_cm=");
  ASSERT_NE(summary, std::string::npos) << text;
  EXPECT_NE(text.find("summary: model=model split=test e_verts_cm="), std::string::npos) << text;
  const std::string line = text.substr(summary, text.find('\n', summary) - summary);
  char lbs_text[32], floor_text[32];
  std::snprintf(lbs_text, sizeof lbs_text, " lbs_e_verts_cm=%.3f ", lbs);
  std::snprintf(floor_text, sizeof floor_text, " noise_floor_cm=%.3f", floor);
  EXPECT_NE(line.find(lbs_text), std::string::npos) << line;
  EXPECT_NE(line.find(floor_text), std::string::npos) << line;
  // baseline is evaluate without a model: the same LBS rows.
  ASSERT_EQ(pleat_test::run_command(trainer + " baseline " + root + "/config.json 2>/dev/null", &baseline),
            0);
  EXPECT_NE(baseline.find(text.substr(text.find(row), text.find('\n', text.find(row)) - text.find(row))),
            std::string::npos)
      << baseline;
  EXPECT_EQ(baseline.find("summary:"), std::string::npos) << "no model, no summary";

  // --stages adds a row per earlier stage; the whole model's row stays the same.
  std::string staged;
  ASSERT_EQ(pleat_test::run_command(trainer + " evaluate " + root + "/config.json --stages --model " + root +
                                        "/run/model.pleat 2>&1",
                                    &staged),
            0)
      << staged;
  EXPECT_NE(staged.find("| model, skinning stage | "), std::string::npos) << staged;
  EXPECT_NE(staged.find("| model, blend-shape stage | "), std::string::npos) << staged;
  const auto model_row = [](const std::string& report) {
    const size_t at = report.find("| model | ");
    return at == std::string::npos ? std::string() : report.substr(at, report.find('\n', at) - at);
  };
  EXPECT_FALSE(model_row(text).empty()) << text;
  EXPECT_EQ(model_row(staged), model_row(text));

  // --top-k overrides the model's default_top_k (4): one joint per vertex
  // skins the skirt differently, and a count below 1 is refused.
  std::string single;
  ASSERT_EQ(pleat_test::run_command(trainer + " evaluate " + root + "/config.json --top-k 1 --model " + root +
                                        "/run/model.pleat 2>&1",
                                    &single),
            0)
      << single;
  EXPECT_FALSE(model_row(single).empty()) << single;
  EXPECT_NE(model_row(single), model_row(text));
  EXPECT_EQ(pleat_test::run_command(trainer + " evaluate " + root + "/config.json --top-k 0 --model " + root +
                                        "/run/model.pleat 2>&1",
                                    &single),
            2);
  EXPECT_NE(single.find("--top-k needs a count of at least 1"), std::string::npos) << single;

  std::ofstream(root + "/both.json") << R"({"dataset": "set", "train": ["set/skirt_walk"],
      "schedule": "schedule.json", "output": "x"})";
  EXPECT_EQ(pleat_test::run_command(trainer + " evaluate " + root + "/both.json 2>&1", &text), 1);
  EXPECT_NE(text.find("give either \"dataset\""), std::string::npos) << text;
  std::ofstream(root + "/none.json")
      << R"({"dataset": "nothing", "schedule": "schedule.json", "output": "x"})";
  EXPECT_EQ(pleat_test::run_command(trainer + " evaluate " + root + "/none.json 2>&1", &text), 1);
  EXPECT_NE(text.find("splits.json is missing"), std::string::npos) << text;

  // A data set with test sequences only (datagen still running): the floor
  // and LBS can be read already, but nothing can be trained on it.
  std::ofstream(root + "/set/splits.json") << R"({"train": [], "validation": [], "test": ["skirt_walk"],
      "twins": {"skirt_walk": "skirt_walk.twin"}})";
  ASSERT_EQ(pleat_test::run_command(trainer + " baseline " + root + "/config.json 2>&1", &baseline), 0)
      << baseline;
  EXPECT_NE(baseline.find(floor_row), std::string::npos) << baseline;
  std::string refused;
  EXPECT_EQ(pleat_test::run_command(trainer + " train " + root + "/config.json 2>&1", &refused), 1);
  EXPECT_NE(refused.find("training config '" + root + "/config.json': no training sequence"),
            std::string::npos)
      << refused;

  // --by-clip: a row per clip, named as datagen names it (stem, x<speed>),
  // each scored on its own sequences: the walk's row repeats the walk's
  // numbers above; the other clip has no twin, so no floor. --by-sequence:
  // the same, a row per sequence folder.
  const std::string fast = pleat_test::write_skirt_walk(root + "/set", 0.03, "skirt_fast");
  nlohmann::json meta;
  std::ifstream(fast + "/meta.json") >> meta;
  meta["motion"]["source"] = "/clips/75_02.bvh";
  meta["simulator"]["motion_speed"] = 1.3;
  meta["simulator"]["held_out_garment"] = true;
  std::ofstream(fast + "/meta.json") << meta.dump();
  std::ofstream(root + "/set/splits.json") << R"({"train": [], "validation": [],
      "test": ["skirt_walk", "skirt_fast"], "twins": {"skirt_walk": "skirt_walk.twin"}})";
  std::string clips;
  ASSERT_EQ(pleat_test::run_command(trainer + " evaluate " + root +
                                        "/config.json --splits test --by-clip --by-sequence --errors " +
                                        root + "/errors --model " + root + "/run/model.pleat 2>&1",
                                    &clips),
            0)
      << clips;
  const std::string walk_model = model_row(staged).substr(std::string("| model | ").size());
  char walk_row[160];
  std::snprintf(walk_row, sizeof walk_row, "| 12_03_walk_121 | 1 | 31 | %.3f | %.3f | %.3f | %.2f |", lbs,
                floor, std::stod(walk_model), std::stod(walk_model) / lbs);
  EXPECT_NE(
      clips.find("#### Test split by clip (E_verts cm)\n\n| clip | sequences | frames | LBS | noise floor | "
                 "model | ratio |"),
      std::string::npos)
      << clips;
  EXPECT_NE(clips.find(walk_row), std::string::npos) << walk_row << "\n" << clips;
  const size_t other = clips.find("| 75_02x1.3 | 1 | 31 | ");
  ASSERT_NE(other, std::string::npos) << clips;
  const double other_lbs = std::stod(clips.substr(other + 22));
  EXPECT_GT(other_lbs, lbs) << "its skirt is pushed further out";
  EXPECT_NE(clips.find(" |  | ", other), std::string::npos) << "no twin, no floor: " << clips;
  const size_t by_sequence = clips.find(
      "#### Test split by sequence (E_verts cm)\n\n| sequence | sequences | frames | LBS | noise floor | "
      "model | ratio |");
  ASSERT_NE(by_sequence, std::string::npos) << clips;
  const std::string walk_numbers = std::string(walk_row).substr(std::string("| 12_03_walk_121").size());
  EXPECT_NE(clips.find("| skirt_walk" + walk_numbers, by_sequence), std::string::npos) << clips;
  EXPECT_NE(clips.find("| skirt_fast | 1 | 31 | ", by_sequence), std::string::npos) << clips;
  // Its garment is held out, so the test split is also scored seen / held
  // out, each with its summary line: held out is that one sequence.
  const size_t held_out = clips.find("summary: model=model split=test_held_out e_verts_cm=");
  ASSERT_NE(held_out, std::string::npos) << clips;
  char held_out_tail[80];
  std::snprintf(held_out_tail, sizeof held_out_tail, " lbs_e_verts_cm=%.3f noise_floor_cm=none", other_lbs);
  const std::string held_out_line = clips.substr(held_out, clips.find('\n', held_out) - held_out);
  EXPECT_NE(held_out_line.find(held_out_tail), std::string::npos) << held_out_line;
  char seen_line[160];
  std::snprintf(
      seen_line, sizeof seen_line,
      "summary: model=model split=test_seen e_verts_cm=%.3f lbs_e_verts_cm=%.3f noise_floor_cm=%.3f\n",
      std::stod(walk_model), lbs, floor);
  EXPECT_NE(clips.find(seen_line), std::string::npos) << seen_line << "\n" << clips;

  // --errors: the walk's distance per frame and per vertex; the mean of
  // either column is that sequence's E_verts in the report (LBS, floor,
  // model). The fast clip has no twin: an empty floor column.
  const auto read_csv = [](const std::string& path, std::string* header) {
    std::ifstream in(path);
    std::getline(in, *header);
    std::vector<std::vector<std::string>> rows;
    for (std::string line; std::getline(in, line);) {
      std::vector<std::string> cells;
      std::stringstream cell_stream(line);
      for (std::string cell; std::getline(cell_stream, cell, ',');) cells.push_back(cell);
      if (!line.empty() && line.back() == ',') cells.emplace_back();
      rows.push_back(cells);
    }
    return rows;
  };
  const auto column_mean = [](const std::vector<std::vector<std::string>>& rows, size_t column) {
    double sum = 0.0;
    for (const auto& r : rows) sum += std::stod(r.at(column));
    return sum / static_cast<double>(rows.size());
  };
  std::string header;
  const auto frames = read_csv(root + "/errors/test/skirt_walk_frames.csv", &header);
  EXPECT_EQ(header, "frame,lbs_cm,noise_floor_cm,model_cm");
  ASSERT_EQ(frames.size(), 31u);
  EXPECT_EQ(frames[30][0], "30");
  const auto vertices = read_csv(root + "/errors/test/skirt_walk_vertices.csv", &header);
  EXPECT_EQ(header, "vertex,rest_x,rest_y,rest_z,lbs_cm,noise_floor_cm,model_cm");
  const pleat::SequenceData walk_sequence = pleat::read_sequence(root + "/set/skirt_walk");
  ASSERT_EQ(vertices.size(), static_cast<size_t>(walk_sequence.garment_rest.vertex_count()));
  for (int k = 0; k < 3; ++k)  // the rest position, in metres
    EXPECT_NEAR(std::stod(vertices[7].at(1 + k)), walk_sequence.garment_rest.vertices(7, k), 1e-5);
  const double expected[] = {lbs, floor, std::stod(walk_model)};
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(column_mean(frames, 1 + k), expected[k], 6e-4) << header;
    EXPECT_NEAR(column_mean(vertices, 4 + k), expected[k], 6e-4) << header;
  }
  // Each prediction's cache in garment.obj's vertex order: its distance to
  // the simulated garment.pc2 is the sequence's E_verts again.
  for (const auto& [column, e_verts] : {std::pair<std::string, double>{"lbs", lbs}, {"model", expected[2]}}) {
    const std::string path = root + "/errors/test/skirt_walk_" + column + ".pc2";
    const pleat::CacheHeader cache = pleat::read_cache_header(path, pleat::CacheFormat::pc2);
    ASSERT_EQ(cache.frame_count, 31) << path;
    ASSERT_EQ(cache.vertex_count, walk_sequence.garment_rest.vertex_count()) << path;
    EXPECT_DOUBLE_EQ(cache.frame_rate, 30.0);
    std::vector<float> predicted(walk_sequence.garment_frames.size());
    pleat::read_cache(path, pleat::CacheFormat::pc2, predicted.data(), 0, predicted.size());
    double sum = 0.0;
    for (size_t p = 0; p < predicted.size(); p += 3)
      sum += 100.0 * Eigen::Vector3d(predicted[p] - walk_sequence.garment_frames[p],
                                     predicted[p + 1] - walk_sequence.garment_frames[p + 1],
                                     predicted[p + 2] - walk_sequence.garment_frames[p + 2])
                         .norm();
    EXPECT_NEAR(sum / double(predicted.size() / 3), e_verts, 6e-4) << path;
  }
  const auto fast_frames = read_csv(root + "/errors/test/skirt_fast_frames.csv", &header);
  ASSERT_EQ(fast_frames.size(), 31u);
  EXPECT_EQ(fast_frames[0].at(2), "") << "no twin, no floor";
  EXPECT_NEAR(column_mean(fast_frames, 1), other_lbs, 6e-4);
}

// `pleat bench`: every host setting on the test split with its run time and
// Table I metrics, libtorch on the same weights and LBS, the Pareto front
// marked; the numbers are the ones `pleat-train evaluate` reports.
// --against-blender re-simulates the split's first sequence with its datagen
// config in the same run: the simulation is deterministic, so it matches the
// stored ground truth, and it is far slower than the model.
TEST(TrainingCli, BenchAgainstBlenderResimulatesTheGroundTruth) {
  const std::string root = pleat_test::temp_dir("training_bench_blender");
  std::ofstream(root + "/datagen.json")
      << pleat_test::skirt_datagen_config(root, "", "[{\"name\": \"plain\"}]", "{\"train\": 1}");
  std::string text;
  ASSERT_EQ(pleat_test::run_command(
                cli() + " datagen " + root + "/datagen.json --jobs 1 --threads 1 --quiet 2>&1", &text),
            0)
      << text;
  ASSERT_EQ(pleat_test::run_command(cli() + " init-model --body " + pleat_test::asset_dir() + "/body -o " +
                                        root + "/m.pleat 2>&1",
                                    &text),
            0)
      << text;
  std::ofstream(root + "/schedule.json")
      << R"({"phases": [{"name": "supervised", "weights": {"vertex": 1}}]})";
  std::ofstream(root + "/config.json")
      << R"({"dataset": "set", "schedule": "schedule.json", "output": "run"})";
  ASSERT_EQ(pleat_test::run_command(
                cli() + " bench " + root + "/config.json --model " + root + "/m.pleat -o " + root +
                    "/bench --split train --repeats 1 --threads 1 --no-libtorch --against-blender " + root +
                    "/datagen.json 2>&1",
                &text),
            0)
      << text;
  std::ifstream md(root + "/bench/bench.md");
  const std::string markdown((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  const size_t at = markdown.find("Against Blender, same run:");
  ASSERT_NE(at, std::string::npos) << markdown;
  const std::string line = markdown.substr(at);
  const size_t ratio = line.find("**");
  ASSERT_NE(ratio, std::string::npos) << line;
  EXPECT_GT(std::stod(line.substr(ratio + 2)), 10.0) << line;
  const size_t match = line.find("ground truth to ");
  ASSERT_NE(match, std::string::npos) << line;
  EXPECT_LT(std::stod(line.substr(match + 16)), 1e-6) << line;

  // A datagen config that does not make this set: exit 2, named.
  std::ofstream(root + "/other.json") << pleat_test::skirt_datagen_config(
      root + "/elsewhere", "", "[{\"name\": \"other\"}]", "{\"train\": 1}");
  EXPECT_NE(pleat_test::run_command(
                cli() + " bench " + root + "/config.json --model " + root + "/m.pleat -o " + root +
                    "/bench2 --split train --repeats 1 --threads 1 --no-libtorch --against-blender " + root +
                    "/other.json 2>&1",
                &text),
            0);
  EXPECT_NE(text.find("did not produce sequence"), std::string::npos) << text;
}

TEST(TrainingCli, BenchMeasuresEverySettingAgainstTheGroundTruth) {
  const std::string root = pleat_test::temp_dir("training_bench");
  pleat_test::write_skirt_walk(root + "/set");
  std::ofstream(root + "/set/splits.json") << R"({"train": ["skirt_walk"], "validation": [],
      "test": ["skirt_walk"]})";
  ASSERT_NO_FATAL_FAILURE(train_tiny_model(root));
  std::string text, report;
  const std::string trainer = std::filesystem::path(cli()).parent_path().string() + "/pleat-train";
  ASSERT_EQ(pleat_test::run_command(trainer + " evaluate " + root + "/config.json --splits test --model " +
                                        root + "/run/model.pleat 2>/dev/null",
                                    &report),
            0);
  ASSERT_EQ(pleat_test::run_command(cli() + " bench " + root + "/config.json --model " + root +
                                        "/run/model.pleat -o " + root + "/bench --repeats 1 --threads 1 2>&1",
                                    &text),
            0)
      << text;
  std::ifstream csv(root + "/bench/bench.csv");
  std::map<std::string, std::vector<double>>
      rows;  // "engine,setting" -> ms, E_verts, E_mid, E_high, E_curv, body penetration %, pareto
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(
      line,
      "engine,setting,ms_per_frame,e_verts_cm,e_mid_cm,e_high_cm,e_curv,body_penetration_percent,pareto");
  while (std::getline(csv, line)) {
    const size_t close = line.find("\",");
    ASSERT_NE(close, std::string::npos) << line;
    std::vector<double> values;
    std::stringstream rest(line.substr(close + 2));
    for (std::string v; std::getline(rest, v, ',');) values.push_back(std::stod(v));
    ASSERT_EQ(values.size(), 7u) << line;
    rows[line.substr(0, line.find(',')) + ":" + line.substr(line.find('"') + 1, close - line.find('"') - 1)] =
        values;
  }
  ASSERT_EQ(rows.size(), 15u) << "thirteen runtime settings, libtorch, LBS";
  for (const auto& [name, v] : rows) EXPECT_GT(v[0], 0.0) << name << ": a time per frame";
  // The default setting and LBS score what evaluate reports for them.
  const auto reported = [&](const std::string& label) {
    const size_t at = report.find("| " + label + " | ");
    return at == std::string::npos ? -1.0 : std::stod(report.substr(at + label.size() + 5));
  };
  const std::vector<double>& full = rows["pleat:full (default)"];
  const std::vector<double>& lbs = rows["LBS:nearest body weights, reference loop (1 thread, double)"];
  ASSERT_FALSE(full.empty() || lbs.empty()) << text;
  EXPECT_NEAR(full[1], reported("model"), 5e-4) << report;
  EXPECT_NEAR(lbs[1], reported("LBS (nearest body weights)"), 5e-4) << report;
  EXPECT_NE(rows["pleat:full, top-2 skinning"][1], full[1]) << "top-2 skins differently";
  EXPECT_NE(rows["pleat:skinning stage"][1], full[1]);
  // libtorch runs the same weights with the exact softmax: the runtime's
  // exact-skinning setting scores the same, to float rounding.
  const std::vector<double>& torch_row = rows["libtorch:full stage, exact softmax (trainer's forward)"];
  ASSERT_FALSE(torch_row.empty()) << text;
  EXPECT_NEAR(torch_row[1], rows["pleat:full, exact skinning (every joint)"][1], 1e-3);
  EXPECT_NEAR(torch_row[2], rows["pleat:full, exact skinning (every joint)"][2], 1e-3);
  // Pareto: the fastest row and the most accurate row are on the front, and a
  // row that another beats on both is not.
  std::string fastest, most_accurate;
  for (const auto& [name, v] : rows) {
    if (fastest.empty() || v[0] < rows[fastest][0]) fastest = name;
    if (most_accurate.empty() || v[1] < rows[most_accurate][1]) most_accurate = name;
    bool dominated = false;
    for (const auto& [other, o] : rows)
      dominated =
          dominated || (other != name && o[0] <= v[0] && o[1] <= v[1] && (o[0] < v[0] || o[1] < v[1]));
    EXPECT_EQ(v[6], dominated ? 0.0 : 1.0) << name;
  }
  EXPECT_EQ(rows[fastest][6], 1.0) << fastest;
  EXPECT_EQ(rows[most_accurate][6], 1.0) << most_accurate;
  // The skirt is skinned 2 cm outside the body: the post-pass has nothing
  // to push out, and a model that is not LBS may still dip in somewhere.
  const std::vector<double>& pushed = rows["pleat:full + body-collision post-pass (2 mm)"];
  ASSERT_FALSE(pushed.empty()) << text;
  EXPECT_LE(pushed[5], full[5]);
  // The mask leaves the upper half skinned: its error lies between the full
  // model's and the skinning stage's.
  const std::vector<double>& masked = rows["pleat:full, vertex mask: lower half of the garment active"];
  ASSERT_FALSE(masked.empty()) << text;
  EXPECT_NE(masked[1], full[1]);
  EXPECT_NE(masked[1], rows["pleat:skinning stage"][1]);
  std::ifstream md(root + "/bench/bench.md");
  const std::string markdown((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(markdown.find("| pleat | full (default) | "), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("kernel path"), std::string::npos) << "the machine line names the kernel path";
  std::ifstream png(root + "/bench/bench.png", std::ios::binary);
  char magic[8] = {};
  png.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG") << "the plot";

  // A model for another skeleton cannot drive the set's body: exit 2, named.
  const auto other = pleat::runtime::initialize_model(
      pleat::runtime::ModelSkeleton{{"root", "tail"}, {-1, 0}}, {}, pleat::runtime::ModelInitOptions{});
  pleat::runtime::save_model(*other, root + "/other.pleat");
  EXPECT_EQ(pleat_test::run_command(cli() + " bench " + root + "/config.json --model " + root +
                                        "/other.pleat -o " + root + "/other 2>&1",
                                    &text),
            2)
      << text;
  EXPECT_NE(text.find("cannot drive sequence"), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(root + "/other/bench.csv")) << "nothing written";
}

// "dataset" may name several sets: their splits are joined in order, and
// every set's twins are kept (extra training clips beside the set that holds
// validation and test); an entry may take only some of its set's splits.
TEST(TrainingCli, ADataSetListJoinsTheSplits) {
  const std::string root = pleat_test::temp_dir("training_dataset_list");
  std::filesystem::create_directories(root + "/main");
  std::filesystem::create_directories(root + "/extra");
  std::ofstream(root + "/main/splits.json")
      << R"({"train": ["a", "b"], "validation": ["v"], "test": ["t"], "twins": {"t": "t.twin"}})";
  std::ofstream(root + "/extra/splits.json") << R"({"train": ["c"], "validation": [], "test": []})";
  std::ofstream(root + "/schedule.json")
      << R"({"phases": [{"name": "supervised", "weights": {"vertex": 100}}]})";
  std::ofstream(root + "/config.json")
      << R"({"dataset": ["main", "extra"], "schedule": "schedule.json", "output": "run"})";
  const pleat::training::TrainerConfig c = pleat::training::read_trainer_config(root + "/config.json");
  EXPECT_EQ(c.train, (std::vector<std::string>{root + "/main/a", root + "/main/b", root + "/extra/c"}));
  EXPECT_EQ(c.validation, std::vector<std::string>{root + "/main/v"});
  EXPECT_EQ(c.test, std::vector<std::string>{root + "/main/t"});
  ASSERT_EQ(c.twins.size(), 1u);
  EXPECT_EQ(c.twins.at(root + "/main/t"), root + "/main/t.twin");
  // {"name", "splits"} takes only the named splits: extra's training clips
  // join, its validation, test and twins stay out.
  std::ofstream(root + "/extra/splits.json")
      << R"({"train": ["c"], "validation": ["w"], "test": ["u"], "twins": {"u": "u.twin"}})";
  std::ofstream(root + "/selected.json") << R"({"dataset": ["main", {"name": "extra", "splits": ["train"]}],
      "schedule": "schedule.json", "output": "run"})";
  const pleat::training::TrainerConfig s = pleat::training::read_trainer_config(root + "/selected.json");
  EXPECT_EQ(s.train, c.train);
  EXPECT_EQ(s.validation, c.validation);
  EXPECT_EQ(s.test, c.test);
  EXPECT_EQ(s.twins, c.twins);
  std::ofstream(root + "/misspelt.json") << R"({"dataset": ["main", {"name": "extra", "splits": ["tran"]}],
      "schedule": "schedule.json", "output": "run"})";
  try {
    pleat::training::read_trainer_config(root + "/misspelt.json");
    ADD_FAILURE() << "a misspelt split is refused";
  } catch (const pleat::Error& e) {
    EXPECT_NE(std::string(e.what()).find("'tran'"), std::string::npos) << e.what();
  }
  std::ofstream(root + "/missing.json")
      << R"({"dataset": ["main", "nowhere"], "schedule": "schedule.json", "output": "run"})";
  try {
    pleat::training::read_trainer_config(root + "/missing.json");
    ADD_FAILURE() << "a missing set is refused";
  } catch (const pleat::Error& e) {
    EXPECT_NE(std::string(e.what()).find("nowhere"), std::string::npos) << e.what();
  }
}

// Fine-tuning: a run may start from a model file (a shipped model and new
// clips). The network begins with the file's weights, not a fresh draw, and
// a file made for another skeleton is refused, naming it.
TEST(TrainingCli, InitialModelStartsFromTheFilesWeights) {
  const std::string root = pleat_test::temp_dir("training_initial_model");
  pleat_test::write_skirt_walk(root);
  std::ofstream(root + "/schedule.json")
      << R"({"phases": [{"name": "supervised", "weights": {"vertex": 100}}]})";
  const std::string small = R"("model": {"code_width": 8, "body_widths": [8], "garment_widths": [8, 8],
      "gru_layers": 1, "blend_widths": [8, 3], "refinement_widths": [8, 3]})";
  std::ofstream(root + "/fresh.json") << R"({"train": ["skirt_walk"], "schedule": "schedule.json",
      "output": "fresh", "epochs": 1, "batch_frames": 8, "progress": false, "plot": false, )"
                                      << small << "}";
  pleat::training::Trainer fresh(pleat::training::read_trainer_config(root + "/fresh.json"));
  const std::shared_ptr<pleat::runtime::Model> untrained = fresh.export_model();
  fresh.train_epoch();
  pleat::runtime::save_model(*fresh.export_model(), root + "/start.pleat");
  const auto start = pleat::runtime::load_model_file(root + "/start.pleat");

  std::ofstream(root + "/tuned.json") << R"({"train": ["skirt_walk"], "schedule": "schedule.json",
      "output": "tuned", "epochs": 1, "progress": false, "plot": false, "initial_model": "start.pleat"})";
  pleat::training::Trainer tuned(pleat::training::read_trainer_config(root + "/tuned.json"));
  const std::shared_ptr<pleat::runtime::Model> tuned_start = tuned.export_model();
  const auto begins = pleat::runtime::model_tensors(*tuned_start);
  const auto file = pleat::runtime::model_tensors(*start), drawn = pleat::runtime::model_tensors(*untrained);
  ASSERT_EQ(begins.size(), file.size());
  ASSERT_EQ(drawn.size(), file.size());
  size_t moved = 0;
  for (size_t t = 0; t < file.size(); ++t) {
    ASSERT_EQ(begins[t].size(), file[t].size()) << file[t].name;
    for (size_t i = 0; i < file[t].size(); ++i) {
      ASSERT_EQ(begins[t].data[i], file[t].data[i]) << file[t].name << " [" << i << "]";
      moved += drawn[t].data[i] != file[t].data[i];
    }
  }
  EXPECT_GT(moved, 100u) << "one epoch moved the weights away from the fresh draw";

  // Another skeleton: the same network on a body with one joint renamed.
  pleat::runtime::ModelSkeleton other = start->skeleton;
  other.joint_names.back() += "_renamed";
  pleat::runtime::ModelInitOptions options;
  options.code_width = 8;
  options.body_widths = {8};
  options.garment_widths = {8, 8};
  options.gru_layers = 1;
  options.blend_widths = {8, 3};
  options.refinement_widths = {8, 3};
  pleat::runtime::save_model(*pleat::runtime::initialize_model(other, start->shape, options),
                             root + "/other.pleat");
  std::ofstream(root + "/other.json") << R"({"train": ["skirt_walk"], "schedule": "schedule.json",
      "output": "other", "progress": false, "initial_model": "other.pleat"})";
  try {
    pleat::training::Trainer refused(pleat::training::read_trainer_config(root + "/other.json"));
    ADD_FAILURE() << "a model for another skeleton is refused";
  } catch (const pleat::Error& e) {
    EXPECT_NE(std::string(e.what()).find("other.pleat"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("skeleton"), std::string::npos) << e.what();
  }
  std::ofstream(root + "/both.json") << R"({"train": ["skirt_walk"], "schedule": "schedule.json",
      "output": "both", "initial_model": "start.pleat", )"
                                     << small << "}";
  try {
    pleat::training::read_trainer_config(root + "/both.json");
    ADD_FAILURE() << "initial_model with a model section is refused";
  } catch (const pleat::Error& e) {
    EXPECT_NE(std::string(e.what()).find("initial_model and model"), std::string::npos) << e.what();
  }
}

// weight_decay reaches the optimiser: one epoch with a strong decay ends
// with smaller weights than the same run without it; a negative decay is
// refused, naming the key.
TEST(TrainingCli, WeightDecayShrinksTheTrainedWeights) {
  const std::string root = pleat_test::temp_dir("training_weight_decay");
  pleat_test::write_skirt_walk(root);
  std::ofstream(root + "/schedule.json")
      << R"({"phases": [{"name": "supervised", "weights": {"vertex": 100}}]})";
  const auto weight_norm_after_one_epoch = [&](const std::string& name, double decay) {
    std::ofstream(root + "/" + name + ".json")
        << R"({"train": ["skirt_walk"], "schedule": "schedule.json", "output": ")" << name
        << R"(", "epochs": 1, "batch_frames": 8, "progress": false, "plot": false, "weight_decay": )" << decay
        << R"(, "model": {"code_width": 8, "body_widths": [8], "garment_widths": [8, 8], "gru_layers": 1,
        "blend_widths": [8, 3], "refinement_widths": [8, 3]}})";
    pleat::training::Trainer t(pleat::training::read_trainer_config(root + "/" + name + ".json"));
    t.train_epoch();
    const std::shared_ptr<pleat::runtime::Model> model = t.export_model();
    double sum = 0;
    for (const auto& tensor : pleat::runtime::model_tensors(*model))
      if (tensor.name.size() > 7 && tensor.name.compare(tensor.name.size() - 7, 7, " weight") == 0)
        for (size_t i = 0; i < tensor.size(); ++i) sum += double(tensor.data[i]) * tensor.data[i];
    return std::sqrt(sum);
  };
  const double plain = weight_norm_after_one_epoch("plain", 0.0),
               decayed = weight_norm_after_one_epoch("decayed", 50.0);
  EXPECT_LT(decayed, 0.9 * plain) << "a decay of 50 at learning rate 0.003 shrinks each matrix 14 % a step";
  std::ofstream(root + "/negative.json") << R"({"train": ["skirt_walk"], "schedule": "schedule.json",
      "output": "negative", "weight_decay": -1})";
  try {
    pleat::training::read_trainer_config(root + "/negative.json");
    ADD_FAILURE() << "a negative weight_decay is refused";
  } catch (const pleat::Error& e) {
    EXPECT_NE(std::string(e.what()).find("weight_decay"), std::string::npos) << e.what();
  }
}

// `pleat import-sequences`: the parts of a sequence (rest garment OBJ, body,
// clip, PC2 cache of the "simulation") come back as the same training
// sequence pleat wrote, train end to end, and bad caches are refused with
// exit 2, naming the file and the field, before anything of theirs is written.
TEST(TrainingCli, ImportSequencesFromPc2CachesTrainsEndToEnd) {
  const std::string root = pleat_test::temp_dir("training_import");
  const std::string sim = pleat_test::write_skirt_walk(root + "/sim", 0.02, "walk");
  const auto config = [&](const std::string& name, const std::string& output, const std::string& cache,
                          const std::string& extra) {
    std::string entries;
    for (const char* split : {"train", "validation", "test"})
      entries += std::string(entries.empty() ? "" : ",") + R"({"name": "walk_)" + split + R"(", "split": ")" +
                 split + R"(", "garment": "sim/walk/garment.obj", "garment_name": "skirt", "body": ")" +
                 pleat_test::asset_dir() + R"(/body", "motion": ")" + pleat_test::source_dir() +
                 R"(/tests/fixtures/motion/12_03_walk_121.bvh", "cache": ")" + cache + "\"" + extra + "}";
    std::ofstream(root + "/" + name) << R"({"output": ")" + output + R"(", "sequences": [)" + entries + "]}";
    return root + "/" + name;
  };
  std::string text;
  ASSERT_EQ(pleat_test::run_command(cli() + " import-sequences " +
                                        config("import.json", "set", "sim/walk/garment.pc2", "") + " 2>&1",
                                    &text),
            0)
      << text;
  const pleat::SequenceData original = pleat::read_sequence(sim);
  for (const char* split : {"train", "validation", "test"}) {
    const pleat::SequenceData imported = pleat::read_sequence(root + "/set/walk_" + std::string(split));
    EXPECT_EQ(imported.meta.split, split);
    EXPECT_EQ(imported.meta.frame_count, 31);
    EXPECT_EQ(imported.meta.garment_name, "skirt");
    EXPECT_EQ(imported.meta.joint_names, original.meta.joint_names);
    EXPECT_EQ(imported.garment_frames, original.garment_frames);
    ASSERT_EQ(imported.body_frames.size(), original.body_frames.size());
    for (size_t i = 0; i < imported.body_frames.size(); ++i)
      ASSERT_NEAR(imported.body_frames[i], original.body_frames[i], 1e-5) << i;
    ASSERT_EQ(imported.rotations.size(), original.rotations.size());
    for (size_t i = 0; i < imported.rotations.size(); ++i)
      ASSERT_NEAR(imported.rotations[i], original.rotations[i], 1e-6) << i;
  }
  ASSERT_NO_FATAL_FAILURE(train_tiny_model(root));
  EXPECT_TRUE(std::filesystem::exists(root + "/run/model.pleat"));

  // A 24 fps cache, a cache of another mesh, a NaN, a missing file, another unit.
  std::vector<float> frames(31 * 80 * 3);
  pleat::read_cache(sim + "/garment.pc2", pleat::CacheFormat::automatic, frames.data(), 0, frames.size());
  pleat::write_cache(root + "/small.pc2", pleat::CacheFormat::pc2, frames.data(), 31, 5, 240, 30.0, nullptr);
  frames[(3 * 80 + 2) * 3] = std::nanf("");
  std::filesystem::copy_file(sim + "/garment.pc2", root + "/nan.pc2");
  {
    std::fstream poke(root + "/nan.pc2", std::ios::in | std::ios::out | std::ios::binary);
    poke.seekp(32 + (3 * 80 + 2) * 3 * 4);
    poke.write(reinterpret_cast<const char*>(&frames[(3 * 80 + 2) * 3]), 4);
  }
  const std::vector<std::pair<std::string, std::string>> bad = {
      {config("rate.json", "rate", "sim/walk/garment.pc2", R"(, "cache_frame_rate": 24)"),
       "garment.pc2' runs at 24.000000 fps, the data set at 30.000000 (frame_rate"},
      {config("count.json", "count", "small.pc2", ""),
       "small.pc2' has 5 vertices, the rest garment '" + sim + "/garment.obj' 80 (vertex_count)"},
      {config("nan.json", "nan", "nan.pc2", ""), "nan.pc2': frame 3 vertex 2 is not finite"},
      {config("missing.json", "missing", "none.pc2", ""),
       "'sequences[0].cache' names '" + root + "/none.pc2'"},
      {config("unit.json", "unit", "sim/walk/garment.pc2", R"(, "unit_scale": 100)"),
       "cm (mean) from the rest garment skinned to frame 0"}};
  for (const auto& [file, message] : bad) {
    EXPECT_EQ(pleat_test::run_command(cli() + " import-sequences " + file + " 2>&1", &text), 2) << file;
    EXPECT_NE(text.find(message), std::string::npos) << text;
    const std::string out = root + "/" + std::filesystem::path(file).stem().string();
    EXPECT_FALSE(std::filesystem::exists(out + "/walk_train")) << out;
    EXPECT_FALSE(std::filesystem::exists(out + "/splits.json")) << out;
  }
}

TEST(TrainingCli, FitPhysicsReportsTheForceBalanceOfASplit) {
  const std::string root = pleat_test::temp_dir("training_fit_physics");
  pleat_test::write_skirt_walk(root);
  std::ofstream(root + "/schedule.json") << R"({"phases": [{"name": "s", "weights": {"vertex": 100}}]})";
  std::ofstream(root + "/config.json")
      << R"({"train": ["skirt_walk"], "schedule": "schedule.json", "output": "run"})";
  const std::string trainer = std::filesystem::path(cli()).parent_path().string() + "/pleat-train";
  std::string text;
  ASSERT_EQ(pleat_test::run_command(trainer + " fit-physics " + root + "/config.json --stride 5 2>&1", &text),
            0)
      << text;
  // Frames 2, 7, ..., 27 of the 31-frame walk.
  EXPECT_NE(text.find("6 frames of the train split"), std::string::npos) << text;
  double free_fit = 0, held = 0, alone = 0;
  const size_t at = text.find("force residual");
  ASSERT_NE(at, std::string::npos) << text;
  ASSERT_EQ(
      std::sscanf(text.c_str() + at,
                  "force residual |m a - sum k f| / |m a|: %lf free fit, %lf with gravity held at 1, %lf",
                  &free_fit, &held, &alone),
      3)
      << text;
  // Least squares: no fit is worse than the weights it could have chosen (0; gravity alone).
  EXPECT_LE(free_fit, 1.0 + 1e-9);
  EXPECT_LE(held, alone + 1e-9);
  EXPECT_NE(text.find("{\"inertia\": 1, \"bending\": "), std::string::npos) << text;

  EXPECT_EQ(
      pleat_test::run_command(trainer + " fit-physics " + root + "/config.json --split tset 2>&1", &text), 2);
  EXPECT_NE(text.find("--split takes train, validation and test, not 'tset'"), std::string::npos) << text;
  EXPECT_EQ(
      pleat_test::run_command(trainer + " fit-physics " + root + "/config.json --split test 2>&1", &text), 2);
  EXPECT_NE(text.find("the config's test split has no sequences"), std::string::npos) << text;
  // Every vertex within 10 m of the body: nothing free to fit.
  EXPECT_EQ(pleat_test::run_command(trainer + " fit-physics " + root + "/config.json --contact-cm 1000 2>&1",
                                    &text),
            1);
  EXPECT_NE(text.find("no frame after the second with a vertex away from the body"), std::string::npos)
      << text;
}
