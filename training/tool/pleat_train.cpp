// `pleat-train`: the trainer's command line (`pleat train` and `pleat export`
// forward here). It links libtorch, so it lives apart from the `pleat` CLI,
// which only uses the C API.
//
//   pleat-train train config.json [--epochs N]   train (resumes from the output's checkpoint),
//                                                then write <output>/model.pleat
//   pleat-train export config.json -o model.pleat  the latest checkpoint as a model file
//   pleat-train ablation config.json              the four runs of the paper's Table I and
//                                                <output>/ablation.md
//   pleat-train baseline config.json              metrics of plain LBS (nearest body weights)
//                                                on the validation (else training) sequences
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "ablation.h"
#include "core/error.h"
#include "evaluation.h"
#include "runtime/model_file.h"
#include "trainer.h"

namespace {

const char* kUsage =
    "usage: pleat-train train config.json [--epochs N]\n"
    "       pleat-train export config.json -o model.pleat\n"
    "       pleat-train ablation config.json\n"
    "       pleat-train baseline config.json\n"
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
  std::printf("trained %lld epochs; validation E_verts %.3f cm; wrote %s\n",
              static_cast<long long>(trainer.epoch()), r.validation.e_verts_cm, out.c_str());
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

}  // namespace

int main(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  try {
    if (command == "train") return train(argc, argv);
    if (command == "export") return export_model(argc, argv);
    if (command == "ablation") return ablation(argc, argv);
    if (command == "baseline") return baseline(argc, argv);
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
