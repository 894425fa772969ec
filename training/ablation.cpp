#include "ablation.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "capi/pleat.h"
#include "core/error.h"
#include "runtime/model_file.h"

namespace pleat::training {

std::vector<AblationRow> run_ablation(const TrainerConfig& base, const std::string& only) {
  struct Variant {
    const char* name;
    nn::AttentionVariant variant;
    bool frequency_division;
  };
  const Variant variants[] = {{"gat_freqdiv", nn::AttentionVariant::gat, true},
                              {"lgat_freqdiv", nn::AttentionVariant::lgat, true},
                              {"flexigat_plain", nn::AttentionVariant::flexigat, false},
                              {"flexigat_freqdiv", nn::AttentionVariant::flexigat, true}};
  if (!only.empty() && std::none_of(std::begin(variants), std::end(variants),
                                    [&](const Variant& v) { return only == v.name; }))
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         "ablation has no run '" + only + "' (gat_freqdiv, lgat_freqdiv, flexigat_plain, flexigat_freqdiv)");
  std::vector<AblationRow> rows;
  for (const Variant& v : variants) {
    if (!only.empty() && only != v.name) continue;
    TrainerConfig c = base;
    c.output = base.output + "/" + v.name;
    c.model.variant = v.variant;
    c.frequency_division = v.frequency_division;
    if (c.progress) std::fprintf(stderr, "ablation: %s\n", v.name);
    Trainer trainer(c);
    EpochResult result = trainer.run();
    // As `pleat train` leaves a run: the rows' models can be scored on test.
    runtime::save_model(*trainer.export_model(), c.output + "/model.pleat");
    if (trainer.best_epoch() > 0) {  // report what export writes
      result.epoch = trainer.best_epoch();
      result.validation = trainer.best_validation();
    }
    rows.push_back({v.name, result});
  }
  if (!only.empty()) return rows;
  std::filesystem::create_directories(base.output);
  std::ofstream md(base.output + "/ablation.md"), csv(base.output + "/ablation.csv");
  md << "| configuration | E_verts (cm) | E_vnorm (°) | E_fnorm (°) | E_edge (%) | E_curv | E_low (cm) | "
        "E_mid (cm) "
        "| E_high (cm) | self-collision (%) | kept epoch "
        "|\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  csv << "configuration,e_verts_cm,e_vnorm_deg,e_fnorm_deg,e_edge_percent,e_curv,e_low_cm,e_mid_cm,e_high_cm,"
         "self_collision_percent,kept_epoch\n";
  for (const AblationRow& r : rows) {
    const MetricsResult& m = r.result.validation;
    char line[512];
    std::snprintf(line, sizeof line, "%.4f|%.3f|%.3f|%.3f|%.4f|%.4f|%.4f|%.4f|%.3f|%lld", m.e_verts_cm,
                  m.e_vnorm_deg, m.e_fnorm_deg, m.e_edge_percent, m.e_curv, m.e_low_cm, m.e_mid_cm,
                  m.e_high_cm, m.self_collision_percent, static_cast<long long>(r.result.epoch));
    std::string cells = line;
    md << "| " << r.name << " | ";
    for (char ch : cells) md << (ch == '|' ? std::string(" | ") : std::string(1, ch));
    md << " |\n";
    for (char& ch : cells)
      if (ch == '|') ch = ',';
    csv << r.name << ',' << cells << '\n';
  }
  if (!md || !csv) fail(PLEAT_ERROR_IO, "cannot write the ablation table in '" + base.output + "'");
  return rows;
}

}  // namespace pleat::training
