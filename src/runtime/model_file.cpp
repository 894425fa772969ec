#include "runtime/model_file.h"

#include <fstream>
#include <iterator>

#include "capi/pleat.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "schema/model_generated.h"

namespace pleat::runtime {
namespace fb = pleat::schema;

// The file stores the runtime enums by number: pin them together.
static_assert(static_cast<int>(fb::Feature::MAX) == static_cast<int>(Feature::fused_code));
static_assert(static_cast<int>(fb::Feature::joint_rotations_6d) ==
              static_cast<int>(Feature::joint_rotations_6d));
static_assert(static_cast<int>(fb::ActivationKind::MAX) == static_cast<int>(nn::ActivationKind::elu));
static_assert(static_cast<int>(fb::ActivationKind::leaky_relu) ==
              static_cast<int>(nn::ActivationKind::leaky_relu));
static_assert(static_cast<int>(fb::AttentionVariant::MAX) ==
              static_cast<int>(nn::AttentionVariant::flexigat));
static_assert(static_cast<int>(fb::AttentionVariant::lgat) == static_cast<int>(nn::AttentionVariant::lgat));
static_assert(static_cast<int>(fb::HeadMerge::MAX) == static_cast<int>(nn::HeadMerge::mean));
static_assert(static_cast<int>(fb::MotionMode::MAX) == static_cast<int>(MotionMode::window));

namespace {

// ---------------------------------------------------------------- writing

using Builder = flatbuffers::FlatBufferBuilder;
template <typename T>
using Off = flatbuffers::Offset<T>;

Off<fb::Tensor> write_tensor(Builder& b, const float* data, std::vector<uint32_t> shape, size_t count) {
  auto s = b.CreateVector(shape);
  auto d = b.CreateVector(data, count);
  return fb::CreateTensor(b, s, d);
}

Off<fb::Tensor> write_matrix(Builder& b, const nn::MatrixRM& m) {
  return write_tensor(b, m.data(), {static_cast<uint32_t>(m.rows()), static_cast<uint32_t>(m.cols())},
                      static_cast<size_t>(m.size()));
}

// Empty vectors (no bias, gat's unused p/q) are left out of the file.
Off<fb::Tensor> write_vector(Builder& b, const nn::RowVector& v) {
  if (v.size() == 0) return 0;
  return write_tensor(b, v.data(), {static_cast<uint32_t>(v.size())}, static_cast<size_t>(v.size()));
}

Off<fb::Activation> write_activation(Builder& b, const nn::Activation& a) {
  return fb::CreateActivation(b, static_cast<fb::ActivationKind>(a.kind), a.parameter);
}

Off<fb::Normalization> write_normalization(Builder& b, const InputNormalization& n) {
  if (n.empty()) return 0;
  auto shift = b.CreateVector(n.shift.data(), static_cast<size_t>(n.shift.size()));
  auto scale = b.CreateVector(n.scale.data(), static_cast<size_t>(n.scale.size()));
  return fb::CreateNormalization(b, shift, scale);
}

Off<flatbuffers::Vector<fb::Feature>> write_features(Builder& b, const std::vector<Feature>& features) {
  std::vector<fb::Feature> out;
  for (Feature f : features) out.push_back(static_cast<fb::Feature>(f));
  return b.CreateVector(out);
}

Off<fb::Dense> write_dense(Builder& b, const nn::Dense& d) {
  auto name = b.CreateString(d.name);
  auto weight = write_matrix(b, d.weight);
  auto bias = write_vector(b, d.bias);
  return fb::CreateDense(b, name, weight, bias);
}

Off<fb::Mlp> write_mlp(Builder& b, const nn::Mlp& m) {
  std::vector<Off<fb::Dense>> layers;
  for (const nn::Dense& d : m.layers) layers.push_back(write_dense(b, d));
  auto name = b.CreateString(m.name);
  auto list = b.CreateVector(layers);
  auto hidden = write_activation(b, m.hidden_activation);
  auto output = write_activation(b, m.output_activation);
  return fb::CreateMlp(b, name, list, hidden, output);
}

Off<fb::GraphLayer> write_graph_layer(Builder& b, const nn::GraphAttentionLayer& l) {
  auto name = b.CreateString(l.name);
  auto activation = write_activation(b, l.activation);
  auto weight = write_matrix(b, l.weight);
  auto attention = write_matrix(b, l.attention);
  auto p = write_vector(b, l.p);
  auto q = write_vector(b, l.q);
  auto bias = write_vector(b, l.bias);
  return fb::CreateGraphLayer(b, name, static_cast<fb::AttentionVariant>(l.variant),
                              static_cast<fb::HeadMerge>(l.merge), activation, l.heads, weight, attention, p,
                              q, bias, l.negative_slope, l.lipschitz_epsilon);
}

Off<fb::GraphStack> write_graph_stack(Builder& b, const GraphStack& s) {
  std::vector<Off<fb::GraphLayer>> layers;
  for (const auto& l : s.layers) layers.push_back(write_graph_layer(b, l));
  auto features = write_features(b, s.features);
  auto normalization = write_normalization(b, s.normalization);
  auto list = b.CreateVector(layers);
  return fb::CreateGraphStack(b, features, normalization, list);
}

Off<fb::Gru> write_gru(Builder& b, const nn::Gru& g) {
  std::vector<Off<fb::GruLayer>> layers;
  for (const nn::GruLayer& l : g.layers)
    layers.push_back(fb::CreateGruLayer(b, write_matrix(b, l.w_ih), write_matrix(b, l.w_hh),
                                        write_vector(b, l.b_ih), write_vector(b, l.b_hh)));
  auto name = b.CreateString(g.name);
  return fb::CreateGru(b, name, b.CreateVector(layers));
}

Off<fb::TrainingInfo> write_training(Builder& b, const TrainingInfo& t) {
  std::vector<Off<fb::Metric>> metrics;
  for (const TrainingMetric& m : t.metrics)
    metrics.push_back(fb::CreateMetric(b, b.CreateString(m.name), m.value));
  auto list = b.CreateVector(metrics);
  return fb::CreateTrainingInfo(b, b.CreateString(t.dataset), b.CreateString(t.optimizer), t.learning_rate,
                                b.CreateString(t.schedule), t.epochs, t.seed, b.CreateString(t.created),
                                b.CreateString(t.generator), list);
}

// Views of a tensor list, for model_tensors().
void add(std::vector<TensorView>* out, std::string name, const nn::MatrixRM& m) {
  out->push_back({std::move(name), m.data(), m.rows(), m.cols()});
}
void add(std::vector<TensorView>* out, std::string name, const nn::RowVector& v) {
  if (v.size() > 0) out->push_back({std::move(name), v.data(), 1, v.size()});
}
void add_dense(std::vector<TensorView>* out, const std::string& at, const nn::Dense& d) {
  add(out, at + " weight", d.weight);
  add(out, at + " bias", d.bias);
}
void add_stack(std::vector<TensorView>* out, const std::string& what, const GraphStack& s) {
  add(out, what + " normalization shift", s.normalization.shift);
  add(out, what + " normalization scale", s.normalization.scale);
  for (size_t i = 0; i < s.layers.size(); ++i) {
    const std::string at = what + " layer " + std::to_string(i);
    const auto& l = s.layers[i];
    add(out, at + " weight", l.weight);
    add(out, at + " attention", l.attention);
    add(out, at + " p", l.p);
    add(out, at + " q", l.q);
    add(out, at + " bias", l.bias);
  }
}

}  // namespace

std::vector<uint8_t> serialize_model(const Model& m) {
  Builder b(1 << 16);
  // Every scalar is written, so a file reads the same whatever defaults a
  // later schema declares.
  b.ForceDefaults(true);
  std::vector<Off<flatbuffers::String>> names;
  for (const std::string& n : m.skeleton.joint_names) names.push_back(b.CreateString(n));
  auto joint_names = b.CreateVector(names);
  auto skeleton = fb::CreateSkeleton(b, joint_names, b.CreateVector(m.skeleton.parents));
  std::vector<Off<fb::ShapeEntry>> entries;
  for (const ShapeEntry& e : m.shape)
    entries.push_back(fb::CreateShapeEntry(b, b.CreateString(e.name), e.default_value));
  auto shape = b.CreateVector(entries);

  auto body_features = write_features(b, m.body_features);
  auto body_normalization = write_normalization(b, m.body_normalization);
  auto body_encoder = write_mlp(b, m.body_encoder);
  auto body_pool = write_dense(b, m.body_pool);
  auto body_pool_activation = write_activation(b, m.body_pool_activation);
  auto garment_encoder = write_graph_stack(b, m.garment_encoder);
  auto motion_features = write_features(b, m.motion_features);
  auto motion_normalization = write_normalization(b, m.motion_normalization);
  auto motion_encoder = write_gru(b, m.motion_encoder);
  auto skinning = write_dense(b, m.skinning);
  auto blend = write_graph_stack(b, m.blend);
  auto refinement = write_graph_stack(b, m.refinement);
  auto bands = fb::CreateBandSettings(b, m.bands.low_fraction, m.bands.mid_fraction, m.bands.projection);
  auto training = write_training(b, m.training);
  auto generator = b.CreateString("pleat " PLEAT_VERSION_STRING);

  auto root = fb::CreateModel(b, model_format_version(m), generator, skeleton, shape, m.frame_rate,
                              m.window_frames, static_cast<fb::MotionMode>(m.motion_mode), m.default_top_k,
                              body_features, body_normalization, body_encoder, body_pool,
                              body_pool_activation, garment_encoder, motion_features, motion_normalization,
                              motion_encoder, skinning, m.skinning_prior, blend, m.blend_scale, refinement,
                              m.refinement_scale, bands, training, m.body_vertex_stride,
                              m.offset_filter_length, m.skinning_prior_radius, m.skinning_prior_floor);
  fb::FinishModelBuffer(b, root);
  return {b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize()};
}

uint32_t model_format_version(const Model& model) {
  if (refinement_reads_code(model)) return 5;
  if (model.skinning_prior_radius > 0.0f || model.skinning_prior_floor != kDefaultSkinningPriorFloor)
    return 4;
  if (model.offset_filter_length > 0.0f) return 3;
  return model.body_vertex_stride > 1 ? 2 : 1;
}

void save_model(const Model& model, const std::string& path) {
  const std::vector<uint8_t> bytes = serialize_model(model);
  AtomicFile file(path);
  file.write(bytes.data(), bytes.size());
  file.commit();
}

bool is_model_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[8] = {};
  if (!in.read(header, sizeof header)) return false;
  return flatbuffers::BufferHasIdentifier(header, fb::ModelIdentifier());
}

std::shared_ptr<Model> load_model_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(PLEAT_ERROR_IO, "model '" + path + "': cannot open the file");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail(PLEAT_ERROR_IO, "model '" + path + "': cannot read the file");
  return deserialize_model(bytes.data(), bytes.size(), path);
}

std::vector<TensorView> model_tensors(const Model& m) {
  std::vector<TensorView> out;
  add(&out, "body_normalization shift", m.body_normalization.shift);
  add(&out, "body_normalization scale", m.body_normalization.scale);
  for (size_t i = 0; i < m.body_encoder.layers.size(); ++i)
    add_dense(&out, "body_encoder layer " + std::to_string(i), m.body_encoder.layers[i]);
  add_dense(&out, "body_pool", m.body_pool);
  add_stack(&out, "garment_encoder", m.garment_encoder);
  add(&out, "motion_normalization shift", m.motion_normalization.shift);
  add(&out, "motion_normalization scale", m.motion_normalization.scale);
  for (size_t i = 0; i < m.motion_encoder.layers.size(); ++i) {
    const std::string at = "motion_encoder layer " + std::to_string(i);
    const nn::GruLayer& l = m.motion_encoder.layers[i];
    add(&out, at + " w_ih", l.w_ih);
    add(&out, at + " w_hh", l.w_hh);
    add(&out, at + " b_ih", l.b_ih);
    add(&out, at + " b_hh", l.b_hh);
  }
  add_dense(&out, "skinning", m.skinning);
  add_stack(&out, "blend", m.blend);
  add_stack(&out, "refinement", m.refinement);
  return out;
}

}  // namespace pleat::runtime
