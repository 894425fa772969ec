#include "trainer_config.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "capi/pleat.h"
#include "core/error.h"
#include "io/sequence.h"

namespace pleat::training {
namespace {

using Json = nlohmann::json;

[[noreturn]] void bad_config(const std::string& path, const std::string& what) {
  fail(PLEAT_ERROR_FORMAT, "training config '" + path + "': " + what);
}

std::vector<std::string> folders(const Json& j, const std::filesystem::path& base) {
  std::vector<std::string> out;
  for (const Json& d : j) {
    std::filesystem::path p = d.get<std::string>();
    out.push_back((p.is_relative() ? base / p : p).string());
  }
  return out;
}

nn::AttentionVariant variant_named(const std::string& name, const std::string& path) {
  if (name == "flexigat") return nn::AttentionVariant::flexigat;
  if (name == "gat") return nn::AttentionVariant::gat;
  if (name == "lgat") return nn::AttentionVariant::lgat;
  bad_config(path, "model.variant must be flexigat, gat or lgat, got '" + name + "'");
}

std::vector<runtime::Feature> refinement_features_named(const std::vector<std::string>& names,
                                                        const std::string& path) {
  std::vector<runtime::Feature> out;
  for (const std::string& name : names) {
    bool known = false;
    for (int32_t f = 0; f <= static_cast<int32_t>(runtime::Feature::fused_code) && !known; ++f)
      if (name == runtime::feature_name(static_cast<runtime::Feature>(f))) {
        out.push_back(static_cast<runtime::Feature>(f));
        known = true;
      }
    if (!known) bad_config(path, "model.refinement_features has unknown feature '" + name + "'");
  }
  return out;
}

}  // namespace

TrainerConfig read_trainer_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(PLEAT_ERROR_IO, "training config '" + path + "': cannot open the file");
  Json j;
  try {
    j = Json::parse(in);
  } catch (const Json::exception& e) {
    bad_config(path, std::string("not valid JSON: ") + e.what());
  }
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  TrainerConfig c;
  c.source = path;
  try {
    if (j.contains("dataset") || j.contains("dataset_name")) {
      // A data set written by pleat datagen: its splits.json names the folders.
      if (j.contains("train") || j.contains("validation") || j.contains("test") ||
          (j.contains("dataset") && j.contains("dataset_name")))
        bad_config(path, "give either \"dataset\" or \"dataset_name\", or the train/validation/test lists");
      // One data set, or a list whose splits are joined (e.g. a set of extra
      // training clips next to the set that holds validation and test). An
      // entry {"name": set, "splits": [...]} takes only the splits it names,
      // so another set's training sequences can join without its test clips.
      const Json& named = j.contains("dataset") ? j["dataset"] : j["dataset_name"];
      for (const Json& entry : named.is_array() ? named : Json::array({named})) {
        const Json& name = entry.is_object() ? entry.at("name") : entry;
        std::vector<std::string> taken = {"train", "validation", "test"};
        if (entry.is_object() && entry.contains("splits")) {
          taken = entry["splits"].get<std::vector<std::string>>();
          for (const std::string& split : taken)
            if (split != "train" && split != "validation" && split != "test")
              bad_config(path, "data set '" + name.get<std::string>() +
                                   "': splits must name train, validation or test, got '" + split + "'");
        }
        const auto takes = [&](const std::string& split) {
          return std::find(taken.begin(), taken.end(), split) != taken.end();
        };
        std::filesystem::path root;
        if (j.contains("dataset")) {
          root = name.get<std::string>();
          if (root.is_relative()) root = base / root;
        } else {
          root = default_dataset_dir(name.get<std::string>());
        }
        std::ifstream splits_file(root / "splits.json");
        if (!splits_file)
          fail(PLEAT_ERROR_IO, "training config '" + path + "': no data set at '" + root.string() +
                                   "' (splits.json is missing; generate it with pleat datagen)");
        const Json splits = Json::parse(splits_file);
        const std::pair<const char*, std::vector<std::string>*> lists[] = {
            {"train", &c.train}, {"validation", &c.validation}, {"test", &c.test}};
        for (const auto& [split, list] : lists) {
          if (!takes(split)) continue;
          const std::vector<std::string> more = folders(splits.at(split), root);
          list->insert(list->end(), more.begin(), more.end());
        }
        if (takes("test") && splits.contains("twins"))
          for (const auto& [sequence, twin] : splits["twins"].items())
            c.twins[(root / sequence).string()] = (root / twin.get<std::string>()).string();
      }
    } else {
      c.train = folders(j.at("train"), base);
      if (j.contains("validation")) c.validation = folders(j["validation"], base);
      if (j.contains("test")) c.test = folders(j["test"], base);
    }
    const std::filesystem::path schedule = j.at("schedule").get<std::string>();
    c.schedule_source = (schedule.is_relative() ? base / schedule : schedule).string();
    c.schedule = read_schedule(c.schedule_source);
    const std::filesystem::path output = j.at("output").get<std::string>();
    c.output = (output.is_relative() ? base / output : output).string();
    c.epochs = j.value("epochs", c.epochs);
    c.batch_frames = j.value("batch_frames", c.batch_frames);
    c.sequences_per_batch = j.value("sequences_per_batch", c.sequences_per_batch);
    c.learning_rate = j.value("learning_rate", c.learning_rate);
    c.min_learning_rate = j.value("min_learning_rate", c.min_learning_rate);
    c.weight_decay = j.value("weight_decay", c.weight_decay);
    c.seed = j.value("seed", c.seed);
    c.frequency_division = j.value("frequency_division", c.frequency_division);
    c.progress = j.value("progress", c.progress);
    c.plot = j.value("plot", c.plot);
    if (j.contains("initial_model")) {
      if (j.contains("model"))
        bad_config(path,
                   "initial_model and model exclude each other: a model file carries its own "
                   "architecture and settings");
      const std::filesystem::path initial = j["initial_model"].get<std::string>();
      c.initial_model = (initial.is_relative() ? base / initial : initial).string();
    }
    if (j.contains("model")) {
      const Json& m = j["model"];
      c.model.variant = variant_named(m.value("variant", std::string("flexigat")), path);
      c.model.window_frames = m.value("window_frames", c.model.window_frames);
      c.model.default_top_k = m.value("default_top_k", c.model.default_top_k);
      c.model.code_width = m.value("code_width", c.model.code_width);
      c.model.heads = m.value("heads", c.model.heads);
      c.model.gru_layers = m.value("gru_layers", c.model.gru_layers);
      c.model.body_widths = m.value("body_widths", c.model.body_widths);
      c.model.body_vertex_stride = m.value("body_vertex_stride", c.model.body_vertex_stride);
      c.model.garment_widths = m.value("garment_widths", c.model.garment_widths);
      c.model.blend_widths = m.value("blend_widths", c.model.blend_widths);
      c.model.refinement_widths = m.value("refinement_widths", c.model.refinement_widths);
      if (m.contains("refinement_features"))
        c.model.refinement_features =
            refinement_features_named(m["refinement_features"].get<std::vector<std::string>>(), path);
      c.model.offset_filter_length = m.value("offset_filter_length", c.model.offset_filter_length);
      c.model.skinning_prior_radius = m.value("skinning_prior_radius", c.model.skinning_prior_radius);
      c.model.skinning_prior_floor = m.value("skinning_prior_floor", c.model.skinning_prior_floor);
    }
  } catch (const Json::exception& e) {
    bad_config(path, e.what());
  }
  if (c.epochs < 1 || c.batch_frames < 1) bad_config(path, "epochs and batch_frames must be >= 1");
  if (c.sequences_per_batch < 0) bad_config(path, "sequences_per_batch must be >= 0");
  if (!(c.weight_decay >= 0.0 && c.weight_decay * c.learning_rate < 1.0))
    bad_config(path, "weight_decay must be >= 0 and below 1 / learning_rate");
  c.model.seed = c.seed;
  return c;
}

}  // namespace pleat::training
