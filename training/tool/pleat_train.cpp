// `pleat-train`: the trainer's command line (`pleat train` and `pleat export`
// forward here). It links libtorch, so it lives apart from the `pleat` CLI,
// which only uses the C API.
//
//   pleat-train train config.json [--epochs N]   train (resumes from the output's checkpoint),
//                                                then write <output>/model.pleat
//   pleat-train export config.json -o model.pleat  the kept epoch as a model file
//   pleat-train ablation config.json              the four runs of the paper's Table I and
//                                                <output>/ablation.md
//   pleat-train baseline config.json              metrics of plain LBS (nearest body weights)
//                                                on the validation (else training) sequences
//   pleat-train evaluate config.json --model M.pleat [--model N.pleat ...] [--stages] [--top-k K]
//                     [-o report.md]             Table I on the test sequences: LBS and each
//                                                model (run by the runtime, at its default_top_k
//                                                or K joints per vertex), all of them and split
//                                                into seen / held-out garments
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "ablation.h"
#include "core/error.h"
#include "evaluation.h"
#include "io/atomic_file.h"
#include "runtime/model_file.h"
#include "trainer.h"

namespace {

const char* kUsage =
    "usage: pleat-train train config.json [--epochs N]\n"
    "       pleat-train export config.json -o model.pleat\n"
    "       pleat-train ablation config.json\n"
    "       pleat-train baseline config.json\n"
    "       pleat-train evaluate config.json --model M.pleat [--model N.pleat ...] [--stages] "
    "[--top-k K] [-o report.md]\n"
    "config.json: docs/training.md\n";

int train(int argc, char** argv) {
  if (argc < 3) throw std::invalid_argument("train needs a config file");
  pleat::training::TrainerConfig config = pleat::training::read_trainer_config(argv[2]);
  for (int i = 3; i + 1 < argc; i += 2)
    if (std::strcmp(argv[i], "--epochs") == 0) config.epochs = std::stoll(argv[i + 1]);
  pleat::training::Trainer trainer(config);
  if (trainer.epoch() > 0)
    std::fprintf(stderr, "resuming %s at epoch %lld\n", config.output.c_str(),
                 static_cast<long long>(trainer.epoch()));
  const pleat::training::EpochResult r = trainer.run();
  const std::string out = config.output + "/model.pleat";
  pleat::runtime::save_model(*trainer.export_model(), out);
  const bool kept = trainer.best_epoch() > 0;
  std::printf("trained %lld epochs; wrote %s: epoch %lld, validation E_verts %.3f cm\n",
              static_cast<long long>(trainer.epoch()), out.c_str(),
              static_cast<long long>(kept ? trainer.best_epoch() : trainer.epoch()),
              kept ? trainer.best_validation().e_verts_cm : r.validation.e_verts_cm);
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
  std::printf("wrote %s (epoch %lld)\n", argv[4], static_cast<long long>(trainer.epoch()));
  return 0;
}

int ablation(int argc, char** argv) {
  if (argc != 3) throw std::invalid_argument("ablation needs a config file");
  const auto rows = pleat::training::run_ablation(pleat::training::read_trainer_config(argv[2]));
  for (const auto& r : rows)
    std::printf("%-18s E_verts %.3f cm  E_mid %.3f cm\n", r.name.c_str(), r.result.validation.e_verts_cm,
                r.result.validation.e_mid_cm);
  return 0;
}

int baseline(int argc, char** argv) {
  if (argc != 3) throw std::invalid_argument("baseline needs a config file");
  const pleat::training::TrainerConfig c = pleat::training::read_trainer_config(argv[2]);
  const pleat::training::Dataset data(c.validation.empty() ? c.train : c.validation);
  const pleat::MetricsResult m = pleat::training::lbs_baseline(data);
  std::printf("LBS baseline on %zu sequences (%llu frames):\n", data.sequences().size(),
              static_cast<unsigned long long>(m.frame_count));
  std::printf("  E_verts %.4f cm  E_vnorm %.3f deg  E_fnorm %.3f deg  E_edge %.3f %%  E_curv %.4f\n",
              m.e_verts_cm, m.e_vnorm_deg, m.e_fnorm_deg, m.e_edge_percent, m.e_curv);
  std::printf("  E_low %.4f cm  E_mid %.4f cm  E_high %.4f cm  self-collision %.3f %%\n", m.e_low_cm,
              m.e_mid_cm, m.e_high_cm, m.self_collision_percent);
  return 0;
}

bool held_out_garment(const std::string& dir) {
  std::ifstream in(dir + "/meta.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  return j.is_object() && j.contains("simulator") && j["simulator"].value("held_out_garment", false);
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
  std::snprintf(row, sizeof row, "| %s | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f |\n",
                name.c_str(), m.e_verts_cm, m.e_vnorm_deg, m.e_fnorm_deg, m.e_edge_percent, m.e_curv,
                m.e_low_cm, m.e_mid_cm, m.e_high_cm, m.self_collision_percent);
  return row;
}

int evaluate(int argc, char** argv) {
  if (argc < 3) throw std::invalid_argument("evaluate needs a config file");
  const pleat::training::TrainerConfig c = pleat::training::read_trainer_config(argv[2]);
  std::vector<std::string> models;
  std::string output;
  bool stages = false;
  pleat::runtime::InstanceOptions options;
  for (int i = 3; i < argc; ++i) {
    if (std::strcmp(argv[i], "--model") == 0 && i + 1 < argc) {
      models.push_back(argv[++i]);
    } else if (std::strcmp(argv[i], "--stages") == 0) {
      stages = true;
    } else if (std::strcmp(argv[i], "--top-k") == 0 && i + 1 < argc) {
      options.top_k = std::stoi(argv[++i]);
      if (options.top_k < 1) throw std::invalid_argument("--top-k needs a count of at least 1");
    } else if (std::strcmp(argv[i], "-o") == 0 && i + 1 < argc) {
      output = argv[++i];
    } else {
      throw std::invalid_argument(std::string("unknown or incomplete option '") + argv[i] + "'");
    }
  }
  if (c.test.empty()) throw std::invalid_argument("the config names no test sequences");
  std::vector<std::string> seen, held_out;
  for (const std::string& d : c.test) (held_out_garment(d) ? held_out : seen).push_back(d);
  std::vector<std::pair<std::string, std::shared_ptr<const pleat::runtime::Model>>> loaded;
  for (const std::string& m : models)
    loaded.emplace_back(model_label(m, models), pleat::runtime::load_model_file(m));
  std::string report;
  const auto section = [&](const std::string& title, const std::vector<std::string>& dirs) {
    if (dirs.empty()) return;
    std::fprintf(stderr, "evaluating %s (%zu sequences)\n", title.c_str(), dirs.size());
    const pleat::training::Dataset data(dirs);
    const pleat::MetricsResult lbs = pleat::training::lbs_baseline(data);
    report +=
        "\n### " + title + ": " + std::to_string(dirs.size()) + " sequences, " +
        std::to_string(lbs.frame_count) + " frames\n\n" +
        "| | E_verts cm | E_vnorm deg | E_fnorm deg | E_edge % | E_curv | E_low cm | E_mid cm | E_high cm | "
        "self-collision % |\n|---|---|---|---|---|---|---|---|---|---|\n" +
        table_row("LBS (nearest body weights)", lbs);
    for (const auto& [name, model] : loaded) {
      if (stages) {
        report +=
            table_row(name + ", skinning stage",
                      pleat::training::model_metrics(data, model, pleat::runtime::Stage::skinning, options));
        report += table_row(
            name + ", blend-shape stage",
            pleat::training::model_metrics(data, model, pleat::runtime::Stage::blend_shapes, options));
      }
      report += table_row(
          name, pleat::training::model_metrics(data, model, pleat::runtime::Stage::refinement, options));
    }
  };
  section("Test split", c.test);
  if (!seen.empty() && !held_out.empty()) {
    section("Test, garments seen in training", seen);
    section("Test, held-out garments", held_out);
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

}  // namespace

int main(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  try {
    if (command == "train") return train(argc, argv);
    if (command == "export") return export_model(argc, argv);
    if (command == "ablation") return ablation(argc, argv);
    if (command == "baseline") return baseline(argc, argv);
    if (command == "evaluate") return evaluate(argc, argv);
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
