#include "schedule.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "capi/pleat.h"
#include "core/error.h"

namespace pleat::training {
namespace {

using Json = nlohmann::json;

[[noreturn]] void bad(const std::string& source, const std::string& what) {
  fail(PLEAT_ERROR_FORMAT, "schedule '" + source + "': " + what);
}

}  // namespace

const std::vector<std::string>& loss_names() {
  static const std::vector<std::string> names = {"vertex",
                                                 "k_mid",
                                                 "k_high",
                                                 "edge",
                                                 "curvature",
                                                 "normal",
                                                 "collision",
                                                 "self_collision",
                                                 "gravity",
                                                 "stretch",
                                                 "shear",
                                                 "bending",
                                                 "skinning_smoothness",
                                                 "offset_smoothness"};
  return names;
}

Schedule parse_schedule(const std::string& text, const std::string& source) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::exception& e) {
    bad(source, std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object() || !j.contains("phases") || !j["phases"].is_array() || j["phases"].empty())
    bad(source, "needs a non-empty 'phases' list");
  const std::set<std::string> known(loss_names().begin(), loss_names().end());
  const std::set<std::string> keys = {"name", "weights", "scale_supervised", "freeze_encoders", "advance"};
  const std::set<std::string> conditions = {"e_verts_below_cm", "plateau", "loss_below", "epochs"};
  Schedule s;
  for (size_t i = 0; i < j["phases"].size(); ++i) {
    const Json& p = j["phases"][i];
    const std::string at = "phase " + std::to_string(i);
    if (!p.is_object()) bad(source, at + " is not an object");
    for (const auto& [key, value] : p.items())
      if (!keys.count(key)) bad(source, at + ": unknown key '" + key + "'");
    Phase phase;
    try {
      phase.name = p.value("name", at);
      if (p.contains("weights"))
        for (const auto& [name, value] : p["weights"].items()) {
          if (!known.count(name)) bad(source, at + " '" + phase.name + "': unknown loss '" + name + "'");
          const double w = value.get<double>();
          if (!(w >= 0)) bad(source, at + " '" + phase.name + "': weight of '" + name + "' must be >= 0");
          phase.weights[name] = w;
        }
      phase.scale_supervised = p.value("scale_supervised", 1.0);
      if (!(phase.scale_supervised >= 0)) bad(source, at + ": scale_supervised must be >= 0");
      phase.freeze_encoders = p.value("freeze_encoders", false);
      if (p.contains("advance")) {
        const Json& a = p["advance"];
        for (const auto& [key, value] : a.items())
          if (!conditions.count(key)) bad(source, at + ": unknown advance condition '" + key + "'");
        phase.e_verts_below_cm = a.value("e_verts_below_cm", 0.0);
        phase.loss_below = a.value("loss_below", 0.0);
        phase.epochs = a.value("epochs", int64_t{0});
        if (a.contains("plateau")) {
          phase.plateau_epochs = a["plateau"].at("epochs").get<int64_t>();
          phase.plateau_improvement = a["plateau"].at("improvement").get<double>();
          if (phase.plateau_epochs < 1) bad(source, at + ": plateau epochs must be >= 1");
        }
      }
    } catch (const Json::exception& e) {
      bad(source, at + ": " + e.what());
    }
    s.phases.push_back(std::move(phase));
  }
  return s;
}

Schedule read_schedule(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(PLEAT_ERROR_IO, "schedule '" + path + "': cannot open the file");
  std::stringstream text;
  text << in.rdbuf();
  return parse_schedule(text.str(), path);
}

ScheduleState::ScheduleState(Schedule schedule) : schedule_(std::move(schedule)) {
  enter(0);
}

void ScheduleState::enter(size_t index) {
  index_ = index;
  const Phase& p = schedule_.phases[index];
  for (const char* supervised : {"vertex", "edge", "curvature", "normal"})
    if (weights_.count(supervised)) weights_[supervised] *= p.scale_supervised;
  for (const auto& [name, w] : p.weights) weights_[name] = w;
  frozen_ = frozen_ || p.freeze_encoders;
  epochs_in_phase_ = 0;
  history_.clear();
}

bool ScheduleState::end_epoch(double e_verts_cm, double mean_loss) {
  ++epochs_in_phase_;
  history_.push_back(e_verts_cm);
  if (index_ + 1 >= schedule_.phases.size()) return false;
  const Phase& p = phase();
  bool advance = (p.e_verts_below_cm > 0 && e_verts_cm < p.e_verts_below_cm) ||
                 (p.loss_below > 0 && mean_loss < p.loss_below) ||
                 (p.epochs > 0 && epochs_in_phase_ >= p.epochs);
  if (p.plateau_epochs > 0 && static_cast<int64_t>(history_.size()) > p.plateau_epochs) {
    const double before = history_[history_.size() - 1 - static_cast<size_t>(p.plateau_epochs)];
    advance = advance || (before - e_verts_cm) < p.plateau_improvement * before;
  }
  if (advance) enter(index_ + 1);
  return advance;
}

std::string ScheduleState::save() const {
  Json j = {
      {"phase", index_}, {"epochs_in_phase", epochs_in_phase_}, {"history", history_}, {"frozen", frozen_}};
  j["weights"] = weights_;
  return j.dump();
}

void ScheduleState::restore(const std::string& text) {
  const Json j = Json::parse(text);
  index_ = j.at("phase").get<size_t>();
  epochs_in_phase_ = j.at("epochs_in_phase").get<int64_t>();
  history_ = j.at("history").get<std::vector<double>>();
  frozen_ = j.at("frozen").get<bool>();
  weights_ = j.at("weights").get<LossWeights>();
}

}  // namespace pleat::training
