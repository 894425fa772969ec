// `pleat-train`: the trainer's command line (`pleat train` and `pleat export`
// forward here). It links libtorch, so it lives apart from the `pleat` CLI,
// which only uses the C API.
//
//   pleat-train train config.json [--epochs N]   train (resumes from the output's checkpoint),
//                                                then write <output>/model.pleat
//   pleat-train export config.json -o model.pleat  the kept epoch as a model file
//   pleat-train ablation config.json [--only RUN] the four runs of the paper's Table I and
//                                                <output>/ablation.md (--only: that run alone)
//   pleat-train baseline config.json [--splits ...] evaluate without a model: plain LBS (nearest
//                                                body weights) and the noise floor on each split
//   pleat-train evaluate config.json --model M.pleat [--model N.pleat ...] [--stages] [--top-k K]
//                     [--splits train,validation,test] [--by-clip] [--by-sequence] [--errors DIR]
//                     [-o report.md]
//                                                Table I on each split, side by side: LBS, the
//                                                noise floor (where the data set has twins), and
//                                                each model (run by the runtime, at its
//                                                default_top_k or K joints per vertex); the test
//                                                split also into seen / held-out garments;
//                                                --by-clip: E_verts per clip of each split;
//                                                --by-sequence: per sequence; then
//                                                one `summary:` line per model and split;
//                                                --errors: each sequence's vertex distance per
//                                                frame and per vertex as CSV in DIR/<split>/,
//                                                and LBS's and each model's frames as PC2
//   pleat-train fit-physics config.json [--split train] [--stride N] [--contact-cm C]
//                                                the physics terms' weights that best balance the
//                                                forces of the split's simulated frames
//                                                (physics_fit.h): do the losses describe the
//                                                simulator?
//   pleat-train bench config.json --model M.pleat -o DIR [--split test] [--threads N]
//                     [--repeats N] [--no-libtorch] [--against-blender datagen.json]
//                                                run time against error on one split: the runtime
//                                                under each host setting, libtorch on the same
//                                                weights and LBS (and Blender re-simulating the
//                                                split's first sequence); DIR/bench.md, bench.csv,
//                                                bench.png
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "ablation.h"
#include "bench.h"
#include "bench_blender.h"
#include "core/error.h"
#include "error_maps.h"
#include "evaluation.h"
#include "io/atomic_file.h"
#include "io/contact_sheet.h"
#include "io/sequence.h"
#include "physics_fit.h"
#include "runtime/model_file.h"
#include "trainer.h"

namespace {

const char* kUsage =
    "usage: pleat-train train config.json [--epochs N]\n"
    "       pleat-train export config.json -o model.pleat\n"
    "       pleat-train ablation config.json [--only RUN]\n"
    "       pleat-train baseline config.json\n"
    "       pleat-train evaluate config.json --model M.pleat [--model N.pleat ...] [--stages] "
    "[--top-k K] [--splits train,validation,test] [--by-clip] [--by-sequence] [--errors DIR] "
    "[-o report.md]\n"
    "       pleat-train bench config.json --model M.pleat -o DIR [--split test] [--threads N] "
    "[--repeats N] [--no-libtorch] [--against-blender datagen.json]\n"
    "       pleat-train fit-physics config.json [--split train] [--stride N] [--contact-cm C]\n"
    "config.json: docs/training.md\n";

int train(int argc, char** argv) {
  if (argc < 3) throw std::invalid_argument("train needs a config file");
  pleat::training::TrainerConfig config = pleat::training::read_trainer_config(argv[2]);
  for (int i = 3; i < argc; ++i) {
    if (std::strcmp(argv[i], "--epochs") == 0 && i + 1 < argc)
      config.epochs = std::stoll(argv[++i]);
    else
      throw std::invalid_argument(std::string("unknown or incomplete option '") + argv[i] + "'");
  }
  pleat::training::Trainer trainer(config);
  if (trainer.epoch() > 0)
    std::fprintf(stderr, "resuming %s at epoch %lld\n", config.output.c_str(),
                 static_cast<long long>(trainer.epoch()));
  trainer.run();
  const std::string out = config.output + "/model.pleat";
  pleat::runtime::save_model(*trainer.export_model(), out);
  std::printf("trained %lld epochs; wrote %s: epoch %lld, ", static_cast<long long>(trainer.epoch()),
              out.c_str(), static_cast<long long>(trainer.exported_epoch()));
  if (trainer.best_epoch() > 0)
    std::printf("validation E_verts %.3f cm\n", trainer.best_validation().e_verts_cm);
  else
    std::printf("the last (no validation split to choose by)\n");
  return 0;
}

int export_model(int argc, char** argv) {
  if (argc != 5 || std::strcmp(argv[3], "-o") != 0)
    throw std::invalid_argument("export needs config.json -o model.pleat");
  pleat::training::TrainerConfig config = pleat::training::read_trainer_config(argv[2]);
  config.progress = false;
  pleat::training::Trainer trainer(config);
  if (trainer.epoch() == 0)
    throw std::invalid_argument("no checkpoint in '" + config.output + "': train first");
  pleat::runtime::save_model(*trainer.export_model(), argv[4]);
  std::printf("wrote %s (epoch %lld of %lld)\n", argv[4], static_cast<long long>(trainer.exported_epoch()),
              static_cast<long long>(trainer.epoch()));
  return 0;
}

int ablation(int argc, char** argv) {
  std::string only;
  if (argc == 5 && std::strcmp(argv[3], "--only") == 0) only = argv[4];
  if (argc != 3 && only.empty()) throw std::invalid_argument("ablation needs a config file [--only RUN]");
  const auto rows = pleat::training::run_ablation(pleat::training::read_trainer_config(argv[2]), only);
  for (const auto& r : rows)
    std::printf("%-18s E_verts %.3f cm  E_mid %.3f cm\n", r.name.c_str(), r.result.validation.e_verts_cm,
                r.result.validation.e_mid_cm);
  return 0;
}

bool held_out_garment(const std::string& dir) {
  std::ifstream in(dir + "/meta.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  return j.is_object() && j.contains("simulator") && j["simulator"].value("held_out_garment", false);
}

// The clip a datagen sequence was simulated from, named as datagen names it
// (pleat::clip_name); "other" when its meta.json does not say.
std::string sequence_clip(const std::string& dir) {
  std::ifstream in(dir + "/meta.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (!j.is_object() || !j.contains("motion") || !j["motion"].is_object() || !j["motion"].contains("source"))
    return "other";
  const nlohmann::json simulator =
      j.contains("simulator") && j["simulator"].is_object() ? j["simulator"] : nlohmann::json::object();
  return pleat::clip_name(j["motion"].value("source", ""), simulator.value("motion_speed", 1.0),
                          simulator.value("motion_turn_degrees_per_second", 0.0));
}

// A model's row label: its file name without extension, or "folder/name" when
// another model given has the same file name (each run writes model.pleat).
std::string model_label(const std::string& path, const std::vector<std::string>& all) {
  const std::filesystem::path p(path);
  int same_stem = 0;
  for (const std::string& other : all) same_stem += std::filesystem::path(other).stem() == p.stem();
  if (same_stem < 2) return p.stem().string();
  return (p.parent_path().filename() / p.stem()).string();
}

std::string table_row(const std::string& name, const pleat::MetricsResult& m) {
  char row[512];
  std::snprintf(row, sizeof row,
                "| %s | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f |\n",
                name.c_str(), m.e_verts_cm, m.e_vnorm_deg, m.e_fnorm_deg, m.e_edge_percent, m.e_curv,
                m.e_low_cm, m.e_mid_cm, m.e_high_cm, m.self_collision_percent, m.body_penetration_percent);
  return row;
}

// One split of the report: LBS, the noise floor where the data set has twins
// of these sequences, then each model.
struct SplitRows {
  std::string split;  // "train", "validation", "test"
  pleat::MetricsResult lbs, noise_floor;
  bool has_noise_floor = false;
  std::vector<std::pair<std::string, pleat::MetricsResult>> models;
};

using LoadedModels = std::vector<std::pair<std::string, std::shared_ptr<const pleat::runtime::Model>>>;

// Every sequence of a split scored once; the split's rows, its subsets' and
// its clips' are frame-weighted means of these, and the error maps are read
// from the same frames.
struct SplitScores {
  std::vector<std::string> dirs;
  std::vector<pleat::MetricsResult> lbs, noise_floor;  // noise_floor: frame_count 0 without a twin
  // [model][sequence]; skinning and blend-shape stages only with --stages.
  std::vector<std::vector<pleat::MetricsResult>> skinning, blend_shapes, full;
  std::vector<pleat::training::SequenceErrors> errors;  // [sequence], only with --errors
};

SplitScores score_split(const pleat::training::TrainerConfig& c, const std::vector<std::string>& dirs,
                        const pleat::training::Dataset& data, const LoadedModels& models, bool stages,
                        bool errors, const pleat::runtime::InstanceOptions& options) {
  using pleat::runtime::Stage;
  namespace training = pleat::training;
  SplitScores scores;
  scores.dirs = dirs;
  scores.noise_floor.resize(dirs.size());
  scores.full.resize(models.size());
  if (stages) scores.skinning = scores.blend_shapes = scores.full;
  for (size_t i = 0; i < dirs.size(); ++i) {
    const training::TrainingSequence& s = data.sequences()[i];
    training::SequenceErrors e;
    const std::vector<float> lbs = training::lbs_frames(s);
    scores.lbs.push_back(training::sequence_metrics(s, lbs.data()));
    if (errors) e.lbs = training::vertex_errors(s, lbs.data());
    if (const auto t = c.twins.find(dirs[i]); t != c.twins.end()) {
      const training::Dataset twin_data({t->second});
      const training::TrainingSequence& twin = twin_data.sequences().front();
      scores.noise_floor[i] = training::twin_metrics(s, twin, i);
      const torch::Tensor truth = twin.truth.contiguous();
      if (errors) e.noise_floor = training::vertex_errors(s, truth.data_ptr<float>());
    }
    for (size_t m = 0; m < models.size(); ++m) {
      if (stages) {
        scores.skinning[m].push_back(training::sequence_metrics(
            s, training::model_frames(s, models[m].second, Stage::skinning, options).data()));
        scores.blend_shapes[m].push_back(training::sequence_metrics(
            s, training::model_frames(s, models[m].second, Stage::blend_shapes, options).data()));
      }
      const std::vector<float> predicted =
          training::model_frames(s, models[m].second, Stage::refinement, options);
      scores.full[m].push_back(training::sequence_metrics(s, predicted.data()));
      if (errors) e.models.push_back(training::vertex_errors(s, predicted.data()));
    }
    if (errors) scores.errors.push_back(std::move(e));
  }
  return scores;
}

// The sequences of `indices` that have a twin.
std::vector<size_t> with_twin(const SplitScores& scores, const std::vector<size_t>& indices) {
  std::vector<size_t> out;
  for (size_t i : indices)
    if (scores.noise_floor[i].frame_count > 0) out.push_back(i);
  return out;
}

// E_verts per group of a split (`group` names a sequence's group: its clip,
// or the sequence itself), in the order the groups first appear: LBS, the
// noise floor where every sequence of the group has a twin, and each model
// with its ratio to LBS. Shows which motions, or which simulations, a model
// fails on.
std::string group_table(const std::string& title, const std::string& kind, const SplitScores& scores,
                        const LoadedModels& models,
                        const std::function<std::string(const std::string&)>& group) {
  using pleat::training::frame_weighted;
  std::vector<std::pair<std::string, std::vector<size_t>>> clips;
  for (size_t i = 0; i < scores.dirs.size(); ++i) {
    const std::string clip = group(scores.dirs[i]);
    auto it = std::find_if(clips.begin(), clips.end(), [&](const auto& e) { return e.first == clip; });
    if (it == clips.end()) it = clips.insert(clips.end(), {clip, {}});
    it->second.push_back(i);
  }
  std::string table = "\n#### " + title + " by " + kind + " (E_verts cm)\n\n| " + kind +
                      " | sequences | frames | LBS | noise floor |";
  std::string rule = "\n|---|---|---|---|---|";
  for (const auto& model : models) {
    table += " " + model.first + " | ratio |";
    rule += "---|---|";
  }
  table += rule + "\n";
  for (const auto& [clip, indices] : clips) {
    const pleat::MetricsResult lbs = frame_weighted(scores.lbs, indices);
    char cells[96];
    std::snprintf(cells, sizeof cells, " | %zu | %lld | %.3f | ", indices.size(),
                  static_cast<long long>(lbs.frame_count), lbs.e_verts_cm);
    table += "| " + clip + cells;
    if (with_twin(scores, indices).size() == indices.size()) {
      std::snprintf(cells, sizeof cells, "%.3f |", frame_weighted(scores.noise_floor, indices).e_verts_cm);
      table += cells;
    } else {
      table += " |";
    }
    for (const std::vector<pleat::MetricsResult>& full : scores.full) {
      const double e = frame_weighted(full, indices).e_verts_cm;
      std::snprintf(cells, sizeof cells, " %.3f | %.2f |", e, e / lbs.e_verts_cm);
      table += cells;
    }
    table += "\n";
  }
  return table;
}

// The sequence folders of a split named on the command line ("train",
// "validation" or "test"; anything else is refused, naming `flag`).
const std::vector<std::string>& split_folders(const pleat::training::TrainerConfig& c,
                                              const std::string& split, const char* flag) {
  if (split == "train") return c.train;
  if (split == "validation") return c.validation;
  if (split == "test") return c.test;
  throw std::invalid_argument(std::string(flag) + " takes train, validation and test, not '" + split + "'");
}

// A contact sheet beside the report (report_preview.png): the first model
// (blue) and the simulation (orange) on three frames of the split's first
// sequence; returns the Markdown that shows it.
std::string preview(const pleat::training::TrainerConfig& c, const std::string& split,
                    const std::pair<std::string, std::shared_ptr<const pleat::runtime::Model>>& model,
                    const pleat::runtime::InstanceOptions& options, const std::string& report_path) {
  const std::string dir = split_folders(c, split, "--splits").front();
  const pleat::training::Dataset data({dir});
  const pleat::training::TrainingSequence& s = data.sequences().front();
  const std::vector<float> predicted =
      pleat::training::model_frames(s, model.second, pleat::runtime::Stage::refinement, options);
  const torch::Tensor truth = s.truth.contiguous(), body = s.body_positions.contiguous();
  const int64_t n = s.garment->rest.vertex_count(), nb = body.size(1), last = s.frame_count() - 1;
  std::vector<std::vector<pleat::SheetMesh>> sheet;
  for (int64_t f : {int64_t{0}, last / 2, last}) {
    const pleat::SheetMesh posed{
        body.data_ptr<float>() + f * nb * 3, nb, &s.body.rest.triangles, {190, 190, 190}};
    sheet.push_back({posed, {predicted.data() + f * n * 3, n, &s.garment->rest.triangles, {70, 120, 200}}});
    sheet.push_back(
        {posed, {truth.data_ptr<float>() + f * n * 3, n, &s.garment->rest.triangles, {220, 130, 50}}});
  }
  const std::filesystem::path png =
      std::filesystem::path(report_path).replace_extension("").string() + "_preview.png";
  pleat::write_contact_sheet(png.string(), sheet);
  return "\n![" + model.first + " (blue) and the simulation (orange) on " +
         std::filesystem::path(dir).filename().string() + ", frames 0, " + std::to_string(last / 2) +
         " and " + std::to_string(last) + "](" + png.filename().string() + ")\n";
}

int evaluate(int argc, char** argv) {
  if (argc < 3) throw std::invalid_argument("evaluate needs a config file");
  const pleat::training::TrainerConfig c = pleat::training::read_trainer_config(argv[2]);
  std::vector<std::string> models, splits;
  std::string output, errors_dir;
  bool stages = false, by_clip = false, by_sequence = false;
  pleat::runtime::InstanceOptions options;
  for (int i = 3; i < argc; ++i) {
    if (std::strcmp(argv[i], "--model") == 0 && i + 1 < argc) {
      models.push_back(argv[++i]);
    } else if (std::strcmp(argv[i], "--stages") == 0) {
      stages = true;
    } else if (std::strcmp(argv[i], "--by-clip") == 0) {
      by_clip = true;
    } else if (std::strcmp(argv[i], "--by-sequence") == 0) {
      by_sequence = true;
    } else if (std::strcmp(argv[i], "--top-k") == 0 && i + 1 < argc) {
      options.top_k = std::stoi(argv[++i]);
      if (options.top_k < 1) throw std::invalid_argument("--top-k needs a count of at least 1");
    } else if (std::strcmp(argv[i], "--splits") == 0 && i + 1 < argc) {
      std::stringstream list(argv[++i]);
      for (std::string name; std::getline(list, name, ',');) {
        split_folders(c, name, "--splits");  // refuses an unknown name
        splits.push_back(name);
      }
    } else if (std::strcmp(argv[i], "--errors") == 0 && i + 1 < argc) {
      errors_dir = argv[++i];
    } else if (std::strcmp(argv[i], "-o") == 0 && i + 1 < argc) {
      output = argv[++i];
    } else {
      throw std::invalid_argument(std::string("unknown or incomplete option '") + argv[i] + "'");
    }
  }
  if (splits.empty()) splits = {"train", "validation", "test"};
  if (c.test.empty() && std::find(splits.begin(), splits.end(), "test") != splits.end())
    throw std::invalid_argument("the config names no test sequences (or leave test out of --splits)");
  LoadedModels loaded;
  std::vector<std::string> model_names;
  for (const std::string& m : models) {
    model_names.push_back(model_label(m, models));
    loaded.emplace_back(model_names.back(), pleat::runtime::load_model_file(m));
  }
  std::string report;
  std::vector<SplitRows> summary;
  // The rows of the sequences at `indices` of a scored split.
  const auto section = [&](const std::string& title, const std::string& split, const SplitScores& scores,
                           const std::vector<size_t>& indices) {
    using pleat::training::frame_weighted;
    SplitRows rows;
    rows.split = split;
    rows.lbs = frame_weighted(scores.lbs, indices);
    report +=
        "\n### " + title + ": " + std::to_string(indices.size()) + " sequences, " +
        std::to_string(rows.lbs.frame_count) + " frames\n\n" +
        "| | E_verts cm | E_vnorm deg | E_fnorm deg | E_edge % | E_curv | E_low cm | E_mid cm | E_high cm | "
        "self-collision % | body penetration % |\n|---|---|---|---|---|---|---|---|---|---|---|\n" +
        table_row("LBS (nearest body weights)", rows.lbs);
    const std::vector<size_t> twinned = with_twin(scores, indices);
    if (!twinned.empty()) {
      rows.noise_floor = frame_weighted(scores.noise_floor, twinned);
      rows.has_noise_floor = true;
      report += table_row("noise floor (twin simulations, " + std::to_string(twinned.size()) + " of " +
                              std::to_string(indices.size()) + " sequences)",
                          rows.noise_floor);
    }
    for (size_t m = 0; m < loaded.size(); ++m) {
      const std::string& name = loaded[m].first;
      if (stages) {
        report += table_row(name + ", skinning stage", frame_weighted(scores.skinning[m], indices));
        report += table_row(name + ", blend-shape stage", frame_weighted(scores.blend_shapes[m], indices));
      }
      rows.models.emplace_back(name, frame_weighted(scores.full[m], indices));
      report += table_row(name, rows.models.back().second);
    }
    return rows;
  };
  for (const std::string& split : splits) {
    const std::vector<std::string>& dirs = split_folders(c, split, "--splits");
    if (dirs.empty()) continue;
    const std::string title = split == "train"        ? "Training split"
                              : split == "validation" ? "Validation split"
                                                      : "Test split";
    std::fprintf(stderr, "evaluating %s (%zu sequences)\n", title.c_str(), dirs.size());
    const pleat::training::Dataset data(dirs);
    const SplitScores scores = score_split(c, dirs, data, loaded, stages, !errors_dir.empty(), options);
    std::vector<size_t> all(dirs.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = i;
    summary.push_back(section(title, split, scores, all));
    if (!errors_dir.empty())
      pleat::training::write_error_maps(data, scores.errors, model_names, errors_dir + "/" + split);
    if (by_clip) report += group_table(title, "clip", scores, loaded, sequence_clip);
    if (by_sequence)
      report += group_table(title, "sequence", scores, loaded, [](const std::string& dir) {
        return std::filesystem::path(dir).filename().string();
      });
    if (split != "test") continue;
    std::vector<size_t> seen, held_out;
    for (size_t i = 0; i < dirs.size(); ++i) (held_out_garment(dirs[i]) ? held_out : seen).push_back(i);
    if (!seen.empty() && !held_out.empty()) {
      summary.push_back(section("Test, garments seen in training", "test_seen", scores, seen));
      summary.push_back(section("Test, held-out garments", "test_held_out", scores, held_out));
    }
  }
  if (!output.empty() && !loaded.empty())
    report += preview(c, splits.back(), loaded.front(), options, output);
  // One machine-readable line per model and split (issue 22's report format).
  report += "\n";
  for (const SplitRows& rows : summary)
    for (const auto& [name, m] : rows.models) {
      char floor[32] = "none";
      if (rows.has_noise_floor) std::snprintf(floor, sizeof floor, "%.3f", rows.noise_floor.e_verts_cm);
      char line[256];
      std::snprintf(line, sizeof line,
                    "summary: model=%s split=%s e_verts_cm=%.3f lbs_e_verts_cm=%.3f noise_floor_cm=%s\n",
                    name.c_str(), rows.split.c_str(), m.e_verts_cm, rows.lbs.e_verts_cm, floor);
      report += line;
    }
  std::fputs(report.c_str(), stdout);
  if (!output.empty()) {
    pleat::AtomicFile f(output);
    f.write(report);
    f.commit();
    std::fprintf(stderr, "wrote %s\n", output.c_str());
  }
  return 0;
}

int bench(int argc, char** argv) {
  if (argc < 3) throw std::invalid_argument("bench needs a config file");
  const pleat::training::TrainerConfig c = pleat::training::read_trainer_config(argv[2]);
  std::string model_path, output, split = "test", datagen_config;
  pleat::training::BenchOptions options;
  const auto count = [&](int& i, const char* flag) {
    const int value = std::stoi(argv[++i]);
    if (value < 1) throw std::invalid_argument(std::string(flag) + " needs a count of at least 1");
    return value;
  };
  for (int i = 3; i < argc; ++i) {
    if (std::strcmp(argv[i], "--model") == 0 && i + 1 < argc) {
      model_path = argv[++i];
    } else if (std::strcmp(argv[i], "-o") == 0 && i + 1 < argc) {
      output = argv[++i];
    } else if (std::strcmp(argv[i], "--split") == 0 && i + 1 < argc) {
      split = argv[++i];
    } else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      options.threads = count(i, "--threads");
    } else if (std::strcmp(argv[i], "--repeats") == 0 && i + 1 < argc) {
      options.repeats = count(i, "--repeats");
    } else if (std::strcmp(argv[i], "--no-libtorch") == 0) {
      options.libtorch = false;
    } else if (std::strcmp(argv[i], "--against-blender") == 0 && i + 1 < argc) {
      datagen_config = argv[++i];
    } else {
      throw std::invalid_argument(std::string("unknown or incomplete option '") + argv[i] + "'");
    }
  }
  if (model_path.empty() || output.empty()) throw std::invalid_argument("bench needs --model and -o");
  const std::vector<std::string>& dirs = split_folders(c, split, "--split");
  if (dirs.empty()) throw std::invalid_argument("the config names no " + split + " sequences");
  const auto model = pleat::runtime::load_model_file(model_path);
  std::fprintf(stderr, "bench: %s on the %s split (%zu sequences)\n", model_path.c_str(), split.c_str(),
               dirs.size());
  const pleat::training::Dataset data(dirs);
  const pleat::training::BenchReport report =
      pleat::training::run_bench(data, model, pleat::training::default_bench_settings(), options);
  std::string md = "# Run time against error: " + std::filesystem::path(model_path).stem().string() + ", " +
                   split + " split\n\n" + pleat::training::bench_markdown(report);
  if (!datagen_config.empty()) {
    std::error_code error;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
    const std::string tool =
        ((error ? std::filesystem::path(argv[0]) : self).parent_path() / "pleat-datagen").string();
    md += pleat::training::blender_markdown(
        pleat::training::time_blender(tool, datagen_config, data.sequences().front(), output + "/blender",
                                      options.threads),
        report);
  }
  std::fputs(md.c_str(), stdout);
  std::filesystem::create_directories(output);
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"bench.md", md},
                                   {"bench.csv", pleat::training::bench_csv(report)}}) {
    pleat::AtomicFile f(output + "/" + name);
    f.write(text);
    f.commit();
  }
  // A warning, not a failure: the numbers are written whether or not a plot exists.
  const std::string plot = "/usr/bin/python3 '" PLEAT_SCRIPTS_DIR "/plot_bench.py' '" + output +
                           "/bench.csv' '" + output + "/bench.png'";
  if (std::system(plot.c_str()) != 0)
    std::fprintf(stderr, "pleat-train bench: could not plot %s/bench.png (needs python3-matplotlib)\n",
                 output.c_str());
  std::fprintf(stderr, "wrote %s/bench.md, bench.csv, bench.png\n", output.c_str());
  return 0;
}

int fit_physics(int argc, char** argv) {
  if (argc < 3) throw std::invalid_argument("fit-physics needs a config file");
  const pleat::training::TrainerConfig config = pleat::training::read_trainer_config(argv[2]);
  std::string split = "train";
  int64_t stride = 1;
  double contact_cm = 2.0;
  for (int i = 3; i < argc; ++i) {
    const bool value = i + 1 < argc;
    if (std::strcmp(argv[i], "--split") == 0 && value)
      split = argv[++i];
    else if (std::strcmp(argv[i], "--stride") == 0 && value)
      stride = std::stoll(argv[++i]);
    else if (std::strcmp(argv[i], "--contact-cm") == 0 && value)
      contact_cm = std::stod(argv[++i]);
    else
      throw std::invalid_argument(std::string("unknown or incomplete option '") + argv[i] + "'");
  }
  const std::vector<std::string>& dirs = split_folders(config, split, "--split");
  if (dirs.empty()) throw std::invalid_argument("the config's " + split + " split has no sequences");
  if (stride < 1) throw std::invalid_argument("--stride must be >= 1");
  const pleat::training::PhysicsFit fit =
      pleat::training::fit_physics(pleat::training::Dataset(dirs), stride, contact_cm);
  std::printf("%lld frames of the %s split, %lld free vertex coordinates (over %.1f cm from the body)\n",
              static_cast<long long>(fit.frames), split.c_str(), static_cast<long long>(fit.rows),
              contact_cm);
  std::printf(
      "force residual |m a - sum k f| / |m a|: %.3f free fit, %.3f with gravity held at 1, %.3f with "
      "gravity alone\n",
      fit.residual, fit.elastic_residual, fit.gravity_only_residual);
  const auto print = [](const char* what, const std::map<std::string, double>& weights) {
    std::printf("%s\n  {\"inertia\": 1", what);
    for (const auto& [name, k] : weights) std::printf(", \"%s\": %.6g", name.c_str(), k);
    std::printf("}\n");
  };
  print("free fit (gravity is 1 where the simulator's forces are these terms'):", fit.weights);
  print("gravity held at 1 (the weights that match the simulator, if its residual is small):",
        fit.elastic_weights);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::fputs(kUsage, stdout);
      return 0;
    }
  try {
    if (command == "train") return train(argc, argv);
    if (command == "export") return export_model(argc, argv);
    if (command == "ablation") return ablation(argc, argv);
    if (command == "baseline") return evaluate(argc, argv);  // evaluate without a model
    if (command == "evaluate") return evaluate(argc, argv);
    if (command == "bench") return bench(argc, argv);
    if (command == "fit-physics") return fit_physics(argc, argv);
    std::fputs(kUsage, stderr);
    return 2;
  } catch (const pleat::Error& e) {
    std::fprintf(stderr, "pleat-train %s: %s\n", command.c_str(), e.what());
    return 1;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "pleat-train %s: %s\n%s", command.c_str(), e.what(), kUsage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pleat-train %s: %s\n", command.c_str(), e.what());
    return 1;
  }
}
