#include "trainer.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "capi/pleat.h"
#include "core/error.h"
#include "evaluation.h"
#include "io/sequence.h"
#include "runtime/model_file.h"

namespace pleat::training {
namespace {

using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;

std::string iso_now() {
  const std::time_t t = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return text;
}

// The batch bar redraws one line with '\r': in a log file (stderr not a
// terminal) it would be thousands of lines, so there only the epoch lines print.
void progress(int64_t epoch, int64_t epochs, size_t done, size_t total, double loss) {
  static const bool terminal = isatty(fileno(stderr)) != 0;
  if (!terminal) return;
  const int width = 30, filled = total ? static_cast<int>(width * done / total) : width;
  std::fprintf(stderr, "\repoch %lld/%lld [%s%s] %zu/%zu batches  loss %.4f ", static_cast<long long>(epoch),
               static_cast<long long>(epochs), std::string(static_cast<size_t>(filled), '=').c_str(),
               std::string(static_cast<size_t>(width - filled), ' ').c_str(), done, total, loss);
}

Json metrics_json(const MetricsResult& m) {
  Json j = {{"frame_count", m.frame_count}, {"computed", m.computed}};
  for (const TableMetric& metric : table_metrics()) j[metric.name] = m.*metric.field;
  return j;
}

MetricsResult metrics_from_json(const Json& j) {
  MetricsResult m;
  m.frame_count = j.at("frame_count").get<uint64_t>();
  m.computed = j.at("computed").get<uint32_t>();
  for (const TableMetric& metric : table_metrics()) m.*metric.field = j.at(metric.name).get<double>();
  return m;
}

}  // namespace

Trainer::Trainer(TrainerConfig config)
    : config_(std::move(config)),
      train_(config_.train),
      validation_(config_.validation),
      schedule_(config_.schedule),
      rng_(config_.seed) {
  // Checked here, not when reading: evaluate and baseline read configs whose
  // data set has only test sequences so far.
  if (train_.sequences().empty())
    fail(PLEAT_ERROR_FORMAT, "training config '" + config_.source +
                                 "': no training sequence (a data set's splits.json lists them once "
                                 "pleat datagen has simulated them)");
  initial_ = starting_model(train_.sequences().front().body);
  network_ = Network(*initial_);
  optimizer_ = std::make_unique<Adamax>(network_->parameters(), config_.learning_rate);
  std::vector<torch::Tensor> matrices;
  for (const torch::Tensor& p : network_->parameters())
    if (p.dim() >= 2) matrices.push_back(p);
  optimizer_->set_weight_decay(config_.weight_decay, matrices);
  for (const TrainingSequence& s : train_.sequences())
    bound_train_.push_back(std::make_unique<BoundGarment>(*initial_, s.garment, s.body));
  for (const TrainingSequence& s : validation_.sequences())
    bound_validation_.push_back(std::make_unique<BoundGarment>(*initial_, s.garment, s.body));
  for (const Dataset* d : {&train_, &validation_})
    for (const TrainingSequence& s : d->sequences()) {
      auto& entry = garments_[s.garment.get()];
      if (!entry.first) {
        entry.first = std::make_unique<GarmentGeometry>(*s.garment);
        entry.second = std::make_unique<BandProjector>(s.garment->prepared->bands);
      }
    }
  if (!validation_.sequences().empty()) validation_lbs_ = lbs_baseline(validation_);
  train_lbs_ = lbs_baseline(train_);
  std::filesystem::create_directories(config_.output);
  load_checkpoint();
}

std::shared_ptr<runtime::Model> Trainer::starting_model(const Body& body) {
  std::vector<runtime::ShapeEntry> shape;
  for (const ShapeParameter& p : body.shape) shape.push_back({p.name, static_cast<float>(p.default_value)});
  if (config_.initial_model.empty())
    return runtime::initialize_model({body.skeleton.names, body.skeleton.parents}, shape, config_.model);
  std::shared_ptr<runtime::Model> m = runtime::load_model_file(config_.initial_model);
  const std::string where =
      "initial_model '" + config_.initial_model + "' of training config '" + config_.source + "'";
  if (m->skeleton.joint_names != body.skeleton.names || m->skeleton.parents != body.skeleton.parents)
    fail(PLEAT_ERROR_FORMAT, where + ": its skeleton is not the training body's");
  std::vector<std::string> trained, asked;
  for (const runtime::ShapeEntry& e : m->shape) trained.push_back(e.name);
  for (const runtime::ShapeEntry& e : shape) asked.push_back(e.name);
  if (trained != asked)
    fail(PLEAT_ERROR_FORMAT, where + ": its shape parameters are not the training body's");
  // A checkpoint of this run is checked against these, as for a fresh model.
  config_.model.body_vertex_stride = m->body_vertex_stride;
  config_.model.offset_filter_length = m->offset_filter_length;
  config_.model.skinning_prior_radius = m->skinning_prior_radius;
  config_.model.skinning_prior_floor = m->skinning_prior_floor;
  return m;
}

std::vector<LossTerm> Trainer::batch_loss(const TrainingSequence& s, const std::vector<int64_t>& frames,
                                          double* vertex_cm) {
  const size_t index = static_cast<size_t>(&s - train_.sequences().data());
  const NetworkOutput out =
      network_->forward(*bound_train_[index], s.poses(), frames, runtime::Stage::refinement);
  const torch::Tensor at = torch::tensor(frames, torch::kInt64);
  const torch::Tensor truth = s.truth.index_select(0, at), x = out.positions;
  const auto& [geometry, bands] = garments_.at(s.garment.get());
  const LossWeights& w = schedule_.weights();
  const auto weight = [&](const char* name) {
    const auto it = w.find(name);
    return it == w.end() ? 0.0 : it->second;
  };
  const torch::Tensor plain = vertex_loss(x, truth);
  *vertex_cm = plain.item<double>() * 100.0;
  std::vector<LossTerm> terms;
  const auto add = [&](const char* name, const std::function<torch::Tensor()>& term) {
    if (weight(name) > 0) terms.push_back({name, weight(name) * term()});
  };
  add("vertex", [&] {
    return config_.frequency_division
               ? frequency_vertex_loss(*bands, x, truth, weight("k_mid"), weight("k_high")).total
               : plain;
  });
  add("edge", [&] { return edge_loss(*geometry, x, truth); });
  add("curvature", [&] { return curvature_loss(*geometry, x, truth); });
  add("normal", [&] { return normal_loss(*geometry, x, truth); });
  add("skinning_smoothness",
      [&] { return skinning_smoothness_loss(*geometry, out.weights, bound_train_[index]->prior_weights); });
  add("offset_smoothness", [&] {
    return offset_smoothness_loss(*geometry, out.blend) + offset_smoothness_loss(*geometry, x - out.skinned);
  });
  add("collision", [&] {
    return collision_loss(x, s.body_positions.index_select(0, at), s.body_normals.index_select(0, at));
  });
  add("self_collision", [&] { return self_collision_loss(*geometry, x); });
  add("gravity", [&] { return gravity_loss(*geometry, x); });
  add("stretch", [&] { return stretch_loss(*geometry, x); });
  add("shear", [&] { return shear_loss(*geometry, x); });
  add("bending", [&] { return bending_loss(*geometry, x); });
  return terms;
}

std::map<std::string, double> Trainer::gradient_norms(const std::vector<LossTerm>& terms) {
  std::map<std::string, double> norms;
  for (const LossTerm& t : terms) {
    norms[t.name] = 0.0;
    if (!t.value.requires_grad()) continue;  // nothing trained reaches it (frozen, or a constant)
    optimizer_->zero_grad();
    t.value.backward({}, /*retain_graph=*/true);
    double squared = 0;
    for (const torch::Tensor& p : network_->parameters())
      if (p.grad().defined()) squared += p.grad().pow(2).sum().item<double>();
    norms[t.name] = std::sqrt(squared);
  }
  optimizer_->zero_grad();
  return norms;
}

EpochResult Trainer::train_epoch() {
  const auto start = Clock::now();
  EpochResult r;
  r.epoch = epoch_ + 1;
  r.phase = schedule_.phase().name;
  r.learning_rate =
      cosine_learning_rate(config_.learning_rate, config_.min_learning_rate, epoch_, config_.epochs);
  optimizer_->set_learning_rate(r.learning_rate);
  const bool frozen = schedule_.encoders_frozen();
  for (torch::Tensor& p : network_->encoder_parameters()) p.set_requires_grad(!frozen);
  const std::vector<Dataset::Batch> batches =
      train_.epoch(config_.batch_frames, config_.sequences_per_batch, rng_);
  double loss_sum = 0, vertex_sum = 0;
  int64_t frames = 0;
  for (size_t b = 0; b < batches.size(); ++b) {
    optimizer_->zero_grad();
    // One pass per sequence in the batch; the batch's loss is the
    // frame-weighted mean of the parts, one optimiser step for all of them.
    int64_t batch_frames = 0;
    for (const Dataset::Part& part : batches[b]) batch_frames += static_cast<int64_t>(part.frames.size());
    double batch_loss_value = 0;
    for (const Dataset::Part& part : batches[b]) {
      double vertex_cm = 0;
      const double share = double(part.frames.size()) / double(batch_frames);
      const std::vector<LossTerm> terms =
          batch_loss(train_.sequences()[part.sequence], part.frames, &vertex_cm);
      if (b == 0 && &part == &batches[b].front())
        for (const auto& [name, norm] : gradient_norms(terms)) r.terms[name].gradient_norm = norm;
      torch::Tensor loss = torch::zeros({});
      for (const LossTerm& t : terms) {
        loss = loss + t.value;
        r.terms[t.name].loss += t.value.item<double>() * double(part.frames.size());
      }
      loss = loss * share;
      loss.backward();
      batch_loss_value += loss.item<double>();
      vertex_sum += vertex_cm * double(part.frames.size());
    }
    optimizer_->step();
    if (!std::isfinite(batch_loss_value))
      fail(PLEAT_ERROR_NUMERICAL,
           "training diverged: the loss of epoch " + std::to_string(r.epoch) + " is not finite");
    loss_sum += batch_loss_value * double(batch_frames);
    frames += batch_frames;
    if (config_.progress) progress(r.epoch, config_.epochs, b + 1, batches.size(), loss_sum / double(frames));
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  r.frames_per_second = double(frames) / r.seconds;
  r.loss = loss_sum / double(frames);
  r.train_e_verts_cm = vertex_sum / double(frames);
  for (auto& [name, t] : r.terms) t.loss /= double(frames);
  r.validation = validation_.sequences().empty() ? MetricsResult{} : validate(validation_);
  last_validation_ = r.validation;
  if (config_.progress) {
    char validation[64] = "no validation split";
    if (!validation_.sequences().empty())
      std::snprintf(validation, sizeof validation, "validation %.3f cm (LBS %.3f)", r.validation.e_verts_cm,
                    validation_lbs_.e_verts_cm);
    std::fprintf(stderr,
                 "\repoch %lld/%lld %-16s loss %.4f  E_verts train %.3f cm (LBS %.3f), %s  %.1f frames/s\n",
                 static_cast<long long>(r.epoch), static_cast<long long>(config_.epochs), r.phase.c_str(),
                 r.loss, r.train_e_verts_cm, train_lbs_.e_verts_cm, validation, r.frames_per_second);
  }
  ++epoch_;
  schedule_.end_epoch(validation_.sequences().empty() ? r.train_e_verts_cm : r.validation.e_verts_cm, r.loss);
  return r;
}

MetricsResult Trainer::validate(const Dataset& data) {
  torch::NoGradGuard no_grad;
  MetricsResult total;
  for (size_t i = 0; i < data.sequences().size(); ++i) {
    const TrainingSequence& s = data.sequences()[i];
    const BoundGarment& bound = &data == &validation_ ? *bound_validation_[i] : *bound_train_[i];
    const int64_t n = s.garment->rest.vertex_count();
    std::vector<float> predicted(static_cast<size_t>(s.frame_count() * n * 3));
    for (int64_t f = 0; f < s.frame_count(); f += config_.batch_frames) {
      std::vector<int64_t> frames;
      for (int64_t k = f; k < std::min(s.frame_count(), f + config_.batch_frames); ++k) frames.push_back(k);
      const torch::Tensor x =
          network_->forward(bound, s.poses(), frames, runtime::Stage::refinement).positions.contiguous();
      std::copy(x.data_ptr<float>(), x.data_ptr<float>() + x.numel(), predicted.data() + f * n * 3);
    }
    accumulate(&total, sequence_metrics(s, predicted.data()));
  }
  return total;
}

EpochResult Trainer::run(int64_t stop_after) {
  EpochResult last;
  const int64_t end = stop_after > 0 ? std::min(stop_after, config_.epochs) : config_.epochs;
  while (epoch_ < end) {
    last = train_epoch();
    log(last);
    keep_if_best(last);
    save_checkpoint();
  }
  if (config_.plot && epoch_ > 0) plot();
  return last;
}

void Trainer::plot() const {
  // A warning, not a failure: the model is trained whether or not a plot exists.
  const std::string command = "/usr/bin/python3 '" PLEAT_SCRIPTS_DIR "/plot_training.py' '" + config_.output +
                              "/log.csv' '" + config_.output + "/curves.png'";
  if (std::system(command.c_str()) != 0)
    std::fprintf(stderr, "pleat-train: could not plot %s/curves.png (needs python3-matplotlib)\n",
                 config_.output.c_str());
}

void Trainer::log(const EpochResult& r) const {
  const std::string path = config_.output + "/log.csv";
  const bool fresh = !std::filesystem::exists(path);
  std::ofstream out(path, std::ios::app);
  if (fresh)
    out << "epoch,phase,learning_rate,loss,train_e_verts_cm,e_verts_cm,e_vnorm_deg,e_fnorm_deg,e_edge_"
           "percent,"
           "e_curv,e_low_cm,e_mid_cm,e_high_cm,self_collision_percent,seconds,frames_per_second,train_lbs_e_"
           "verts_cm,lbs_e_verts_cm\n";
  const MetricsResult& v = r.validation;
  out << r.epoch << ',' << r.phase << ',' << r.learning_rate << ',' << r.loss << ',' << r.train_e_verts_cm
      << ',' << v.e_verts_cm << ',' << v.e_vnorm_deg << ',' << v.e_fnorm_deg << ',' << v.e_edge_percent << ','
      << v.e_curv << ',' << v.e_low_cm << ',' << v.e_mid_cm << ',' << v.e_high_cm << ','
      << v.self_collision_percent << ',' << r.seconds << ',' << r.frames_per_second << ','
      << train_lbs_.e_verts_cm << ',' << validation_lbs_.e_verts_cm << '\n';
  if (!out) fail(PLEAT_ERROR_IO, "cannot append to '" + path + "'");
  const std::string terms_path = config_.output + "/terms.csv";
  const bool fresh_terms = !std::filesystem::exists(terms_path);
  std::ofstream terms(terms_path, std::ios::app);
  if (fresh_terms) terms << "epoch,term,loss,gradient_norm\n";
  for (const auto& [name, t] : r.terms)
    terms << r.epoch << ',' << name << ',' << t.loss << ',' << t.gradient_norm << '\n';
  if (!terms) fail(PLEAT_ERROR_IO, "cannot append to '" + terms_path + "'");
}

void Trainer::keep_if_best(const EpochResult& r) {
  if (validation_.sequences().empty()) return;
  if (best_epoch_ == 0 || r.validation.e_verts_cm < best_validation_.e_verts_cm) {
    best_epoch_ = r.epoch;
    best_validation_ = r.validation;
    best_parameters_.clear();
    for (const torch::Tensor& p : network_->parameters()) best_parameters_.push_back(p.detach().clone());
    const std::string path = config_.output + "/best.pt";
    torch::save(best_parameters_, path + ".tmp");
    std::filesystem::rename(path + ".tmp", path);
  }
  if (config_.progress)
    std::fprintf(
        stderr,
        "epoch %lld: validation E_verts %.3f x LBS, worst metric %.3f x LBS; kept epoch %lld (E_verts "
        "%.3f cm)\n",
        static_cast<long long>(r.epoch), r.validation.e_verts_cm / validation_lbs_.e_verts_cm,
        worst_ratio(r.validation, validation_lbs_), static_cast<long long>(best_epoch_),
        best_validation_.e_verts_cm);
}

void Trainer::save_checkpoint() const {
  std::vector<torch::Tensor> tensors;
  for (const torch::Tensor& p : network_->parameters()) tensors.push_back(p.detach());
  for (const torch::Tensor& t : optimizer_->state()) tensors.push_back(t);
  const std::string base = config_.output + "/checkpoint";
  torch::save(tensors, base + ".pt.tmp");
  std::ostringstream rng;
  rng << rng_;
  const Json meta = {{"epoch", epoch_},
                     {"parameters", network_->parameters().size()},
                     {"body_vertex_stride", config_.model.body_vertex_stride},
                     {"offset_filter_length", config_.model.offset_filter_length},
                     {"skinning_prior_radius", config_.model.skinning_prior_radius},
                     {"skinning_prior_floor", config_.model.skinning_prior_floor},
                     {"best_epoch", best_epoch_},
                     {"best_validation", metrics_json(best_validation_)},
                     {"schedule", schedule_.save()},
                     {"rng", rng.str()}};
  {
    std::ofstream out(base + ".json.tmp");
    out << meta.dump(2) << '\n';
    if (!out) fail(PLEAT_ERROR_IO, "cannot write '" + base + ".json.tmp'");
  }
  // The tensors land first: a checkpoint.json always describes a complete .pt.
  std::filesystem::rename(base + ".pt.tmp", base + ".pt");
  std::filesystem::rename(base + ".json.tmp", base + ".json");
}

bool Trainer::load_checkpoint() {
  const std::string base = config_.output + "/checkpoint";
  if (!std::filesystem::exists(base + ".json")) return false;
  std::ifstream in(base + ".json");
  const Json meta = Json::parse(in);
  std::vector<torch::Tensor> tensors;
  torch::load(tensors, base + ".pt");
  std::vector<torch::Tensor> parameters = network_->parameters();
  if (meta.at("parameters").get<size_t>() != parameters.size() || tensors.size() < parameters.size())
    fail(PLEAT_ERROR_FORMAT, "checkpoint '" + base + "' was made for another architecture");
  for (size_t i = 0; i < parameters.size(); ++i)
    if (!tensors[i].sizes().equals(parameters[i].sizes()))
      fail(PLEAT_ERROR_FORMAT, "checkpoint '" + base + "' was made for another architecture (tensor " +
                                   std::to_string(i) + " has another shape)");
  // Same tensors, another network: the parameter count cannot tell.
  const auto same_setting = [&](const char* key, double trained, double asked) {
    if (trained == asked) return;
    std::ostringstream message;
    message << "checkpoint '" << base << "' was trained with " << key << " " << trained
            << ", the config asks for " << asked;
    fail(PLEAT_ERROR_FORMAT, message.str());
  };
  same_setting("body_vertex_stride", meta.value("body_vertex_stride", 1), config_.model.body_vertex_stride);
  same_setting("offset_filter_length", meta.value("offset_filter_length", 0.0f),
               config_.model.offset_filter_length);
  same_setting("skinning_prior_radius", meta.value("skinning_prior_radius", 0.0f),
               config_.model.skinning_prior_radius);
  same_setting("skinning_prior_floor",
               meta.value("skinning_prior_floor", runtime::kDefaultSkinningPriorFloor),
               config_.model.skinning_prior_floor);
  {
    torch::NoGradGuard no_grad;
    for (size_t i = 0; i < parameters.size(); ++i) parameters[i].copy_(tensors[i]);
  }
  optimizer_->load_state(std::vector<torch::Tensor>(
      tensors.begin() + static_cast<std::ptrdiff_t>(parameters.size()), tensors.end()));
  epoch_ = meta.at("epoch").get<int64_t>();
  best_epoch_ = meta.value("best_epoch", int64_t{0});
  if (best_epoch_ > 0) {
    best_validation_ = metrics_from_json(meta.at("best_validation"));
    torch::load(best_parameters_, config_.output + "/best.pt");
    if (best_parameters_.size() != parameters.size())
      fail(PLEAT_ERROR_FORMAT, "'" + config_.output + "/best.pt' does not hold this architecture's weights");
  }
  schedule_.restore(meta.at("schedule").get<std::string>());
  std::istringstream rng(meta.at("rng").get<std::string>());
  rng >> rng_;
  return true;
}

std::shared_ptr<runtime::Model> Trainer::export_model() const {
  std::shared_ptr<runtime::Model> m;
  if (best_epoch_ > 0) {
    Network kept(*initial_);
    torch::NoGradGuard no_grad;
    std::vector<torch::Tensor> parameters = kept->parameters();
    for (size_t i = 0; i < parameters.size(); ++i) parameters[i].copy_(best_parameters_[i]);
    m = kept->to_model();
  } else {
    m = network_->to_model();
  }
  runtime::TrainingInfo& t = m->training;
  t.dataset = std::to_string(train_.sequences().size()) + " training sequences (" +
              std::to_string(train_.frame_count()) + " frames), " +
              std::to_string(validation_.sequences().size()) + " validation";
  t.optimizer = "adamax";
  t.learning_rate = config_.learning_rate;
  t.schedule = "cosine; " + config_.schedule_source;
  if (config_.weight_decay > 0) t.schedule += "; weight decay " + Json(config_.weight_decay).dump();
  if (best_epoch_ > 0)
    t.schedule += "; kept epoch " + std::to_string(best_epoch_) + " of " + std::to_string(epoch_) +
                  " (lowest validation E_verts)";
  t.epochs = exported_epoch();
  t.seed = static_cast<int64_t>(config_.seed);
  t.created = iso_now();
  t.generator = "pleat " PLEAT_VERSION_STRING " trainer";
  const MetricsResult& v = best_epoch_ > 0 ? best_validation_ : last_validation_;
  for (const TableMetric& metric : table_metrics()) t.metrics.push_back({metric.name, v.*metric.field});
  m->source = config_.output + "/model.pleat";
  return m;
}

}  // namespace pleat::training
