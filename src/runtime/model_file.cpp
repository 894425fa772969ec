#include "runtime/model_file.h"

#include <cstring>
#include <fstream>
#include <iterator>

#include "capi/pleat.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "schema/model_generated.h"

namespace pleat::runtime {
namespace fb = pleat::schema;

// The file stores the runtime enums by number: pin them together.
static_assert(static_cast<int>(fb::Feature::MAX) == static_cast<int>(Feature::posed_joint_distances));
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

// ---------------------------------------------------------------- reading

// Structural reading of one file; semantic checks are validate_model's.
class Reader {
 public:
  explicit Reader(const std::string& source) : prefix_("model '" + source + "': ") {}

  [[noreturn]] void bad(const std::string& what) const { fail(PLEAT_ERROR_FORMAT, prefix_ + what); }

  template <typename T>
  const T& need(const T* p, const std::string& field) const {
    if (!p) bad(field + " is missing");
    return *p;
  }

  // Counts of lists are capped before anything is sized from them.
  template <typename T>
  const flatbuffers::Vector<T>& list(const flatbuffers::Vector<T>* v, const std::string& field, uint32_t cap,
                                     bool allow_empty) const {
    const auto& l = need(v, field);
    if (l.size() > cap)
      bad(field + " has " + std::to_string(l.size()) + " entries, at most " + std::to_string(cap));
    if (!allow_empty && l.size() == 0) bad(field + " is empty");
    return l;
  }

  // A tensor of `rank` dimensions whose shape matches its data length.
  // Returns {rows, cols} (rank 1: {1, n}) and the data.
  const float* tensor(const fb::Tensor& t, const std::string& what, uint32_t rank, nn::Index* rows,
                      nn::Index* cols) const {
    const auto& shape = need(t.shape(), what + " shape");
    const auto& data = need(t.data(), what + " data");
    if (shape.size() != rank)
      bad(what + " has rank " + std::to_string(shape.size()) + ", expected " + std::to_string(rank));
    // Two uint32 extents cannot overflow uint64.
    uint64_t product = 1;
    std::string dims;
    for (uint32_t i = 0; i < rank; ++i) {
      product *= shape.Get(i);
      dims += (i ? "x" : "") + std::to_string(shape.Get(i));
    }
    if (product != data.size())
      bad(what + " has shape " + dims + " (" + std::to_string(product) + " values) but " +
          std::to_string(data.size()) + " data values");
    *rows = rank == 2 ? static_cast<nn::Index>(shape.Get(0)) : 1;
    *cols = static_cast<nn::Index>(shape.Get(rank - 1));
    return data.data();
  }

  nn::MatrixRM matrix(const fb::Tensor* t, const std::string& what) const {
    nn::Index rows = 0, cols = 0;
    const float* data = tensor(need(t, what), what, 2, &rows, &cols);
    nn::MatrixRM m(rows, cols);
    // memcpy: the file's floats are only 4-byte aligned.
    if (m.size() > 0) std::memcpy(m.data(), data, static_cast<size_t>(m.size()) * sizeof(float));
    return m;
  }

  // Absent = empty (no bias, unused p/q).
  nn::RowVector vector(const fb::Tensor* t, const std::string& what, bool required) const {
    if (!t && !required) return {};
    nn::Index rows = 0, cols = 0;
    const float* data = tensor(need(t, what), what, 1, &rows, &cols);
    nn::RowVector v(cols);
    if (cols > 0) std::memcpy(v.data(), data, static_cast<size_t>(cols) * sizeof(float));
    return v;
  }

  nn::RowVector floats(const flatbuffers::Vector<float>* v, const std::string& what) const {
    const auto& l = need(v, what);
    nn::RowVector out(static_cast<nn::Index>(l.size()));
    if (l.size() > 0) std::memcpy(out.data(), l.data(), l.size() * sizeof(float));
    return out;
  }

  nn::Activation activation(const fb::Activation* a, const std::string& what) const {
    const auto& act = need(a, what);
    const auto kind = static_cast<int32_t>(act.kind());
    if (kind < 0 || kind > static_cast<int32_t>(fb::ActivationKind::MAX))
      bad(what + " has unknown kind " + std::to_string(kind));
    return {static_cast<nn::ActivationKind>(kind), act.parameter()};
  }

  std::vector<Feature> features(const flatbuffers::Vector<fb::Feature>* v, const std::string& what) const {
    const auto& l = list(v, what, kKMaxFeatures, true);
    std::vector<Feature> out;
    for (uint32_t i = 0; i < l.size(); ++i) {
      const auto f = static_cast<int32_t>(l.Get(i));
      if (f < 0 || f > static_cast<int32_t>(fb::Feature::MAX))
        bad(what + " entry " + std::to_string(i) + " is unknown feature " + std::to_string(f));
      out.push_back(static_cast<Feature>(f));
    }
    return out;
  }

  InputNormalization normalization(const fb::Normalization* n, const std::string& what) const {
    if (!n) return {};
    return {floats(n->shift(), what + " shift"), floats(n->scale(), what + " scale")};
  }

  nn::Dense dense(const fb::Dense& d, const std::string& what, const std::string& default_name) const {
    nn::Dense out;
    out.name = d.name() ? d.name()->str() : default_name;
    out.weight = matrix(d.weight(), what + " weight");
    out.bias = vector(d.bias(), what + " bias", false);
    return out;
  }

  nn::Mlp mlp(const fb::Mlp& m, const std::string& what) const {
    nn::Mlp out;
    out.name = m.name() ? m.name()->str() : what;
    const auto& layers = list(m.layers(), what + " layers", kMaxStackLayers, false);
    for (uint32_t i = 0; i < layers.size(); ++i) {
      const std::string at = what + " layer " + std::to_string(i);
      out.layers.push_back(dense(need(layers.Get(i), at), at, what + "." + std::to_string(i)));
    }
    out.hidden_activation = activation(m.hidden_activation(), what + " hidden_activation");
    out.output_activation = activation(m.output_activation(), what + " output_activation");
    return out;
  }

  nn::GraphAttentionLayer graph_layer(const fb::GraphLayer& l, const std::string& what,
                                      const std::string& default_name) const {
    nn::GraphAttentionLayer out;
    out.name = l.name() ? l.name()->str() : default_name;
    const auto variant = static_cast<int32_t>(l.variant());
    if (variant < 0 || variant > static_cast<int32_t>(fb::AttentionVariant::MAX))
      bad(what + " variant has unknown value " + std::to_string(variant));
    const auto merge = static_cast<int32_t>(l.merge());
    if (merge < 0 || merge > static_cast<int32_t>(fb::HeadMerge::MAX))
      bad(what + " merge has unknown value " + std::to_string(merge));
    if (l.heads() < 1 || l.heads() > nn::kMaxAttentionHeads)
      bad(what + " heads is " + std::to_string(l.heads()) + ", expected 1.." +
          std::to_string(nn::kMaxAttentionHeads));
    out.variant = static_cast<nn::AttentionVariant>(variant);
    out.merge = static_cast<nn::HeadMerge>(merge);
    out.activation = activation(l.activation(), what + " activation");
    out.heads = l.heads();
    out.weight = matrix(l.weight(), what + " weight");
    out.attention = matrix(l.attention(), what + " attention");
    const bool flexible = out.variant == nn::AttentionVariant::flexigat;
    out.p = vector(l.p(), what + " p", flexible);
    out.q = vector(l.q(), what + " q", flexible);
    out.bias = vector(l.bias(), what + " bias", false);
    out.negative_slope = l.negative_slope();
    out.lipschitz_epsilon = l.lipschitz_epsilon();
    return out;
  }

  GraphStack graph_stack(const fb::GraphStack* s, const std::string& what) const {
    const auto& stack = need(s, what);
    GraphStack out;
    out.features = features(stack.features(), what + " features");
    out.normalization = normalization(stack.normalization(), what + " normalization");
    const auto& layers = list(stack.layers(), what + " layers", kMaxStackLayers, false);
    for (uint32_t i = 0; i < layers.size(); ++i) {
      const std::string at = what + " layer " + std::to_string(i);
      out.layers.push_back(graph_layer(need(layers.Get(i), at), at, what + "." + std::to_string(i)));
    }
    return out;
  }

  nn::Gru gru(const fb::Gru* g, const std::string& what) const {
    const auto& gru = need(g, what);
    nn::Gru out;
    out.name = gru.name() ? gru.name()->str() : what;
    const auto& layers = list(gru.layers(), what + " layers", kMaxStackLayers, false);
    for (uint32_t i = 0; i < layers.size(); ++i) {
      const std::string at = what + " layer " + std::to_string(i);
      const auto& l = need(layers.Get(i), at);
      nn::GruLayer layer;
      layer.w_ih = matrix(l.w_ih(), at + " w_ih");
      layer.w_hh = matrix(l.w_hh(), at + " w_hh");
      layer.b_ih = vector(l.b_ih(), at + " b_ih", true);
      layer.b_hh = vector(l.b_hh(), at + " b_hh", true);
      out.layers.push_back(std::move(layer));
    }
    return out;
  }

  static std::string text(const flatbuffers::String* s) { return s ? s->str() : std::string(); }

 private:
  static constexpr uint32_t kKMaxFeatures = static_cast<uint32_t>(kMaxStackFeatures);
  std::string prefix_;
};

void read_skeleton(const Reader& r, const fb::Model& root, Model* m) {
  const auto& skeleton = r.need(root.skeleton(), "skeleton");
  const auto& names = r.list(skeleton.joint_names(), "skeleton joint_names", kMaxModelJoints, false);
  const auto& parents = r.list(skeleton.parents(), "skeleton parents", kMaxModelJoints, false);
  for (uint32_t j = 0; j < names.size(); ++j)
    m->skeleton.joint_names.push_back(
        r.need(names.Get(j), "skeleton joint " + std::to_string(j) + " name").str());
  m->skeleton.parents.assign(parents.begin(), parents.end());
  const auto& shape = r.list(root.shape(), "shape", kMaxModelShapeEntries, true);
  for (uint32_t i = 0; i < shape.size(); ++i) {
    const auto& entry = r.need(shape.Get(i), "shape entry " + std::to_string(i));
    m->shape.push_back(
        {r.need(entry.name(), "shape entry " + std::to_string(i) + " name").str(), entry.default_value()});
  }
}

void read_metadata(const Reader& r, const fb::Model& root, Model* m) {
  if (const fb::BandSettings* bands = root.bands()) {
    m->bands.low_fraction = bands->low_fraction();
    m->bands.mid_fraction = bands->mid_fraction();
    m->bands.projection = bands->projection();
  }
  if (const fb::TrainingInfo* t = root.training()) {
    TrainingInfo& info = m->training;
    info.dataset = Reader::text(t->dataset());
    info.optimizer = Reader::text(t->optimizer());
    info.learning_rate = t->learning_rate();
    info.schedule = Reader::text(t->schedule());
    info.epochs = t->epochs();
    info.seed = t->seed();
    info.created = Reader::text(t->created());
    info.generator = Reader::text(t->generator());
    if (const auto* metrics = t->metrics())
      for (uint32_t i = 0; i < metrics->size(); ++i) {
        const auto& metric = r.need(metrics->Get(i), "training metric " + std::to_string(i));
        info.metrics.push_back({Reader::text(metric.name()), metric.value()});
      }
  }
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

std::shared_ptr<Model> deserialize_model(const uint8_t* data, size_t size, const std::string& source) {
  const Reader r(source);
  if (!data || size < 8 || !flatbuffers::BufferHasIdentifier(data, fb::ModelIdentifier()))
    r.bad("not a model file (identifier PLMD missing)");
  if (size >= FLATBUFFERS_MAX_BUFFER_SIZE) r.bad("file is larger than FlatBuffers allows (2 GiB)");
  // The verifier checks alignment relative to the buffer start and the
  // accessors read scalars in place, so the start must be 8-byte aligned.
  std::vector<uint64_t> aligned;
  if (reinterpret_cast<uintptr_t>(data) % alignof(uint64_t) != 0) {
    aligned.resize((size + 7) / 8);
    std::memcpy(aligned.data(), data, size);
    data = reinterpret_cast<const uint8_t*>(aligned.data());
  }
  // Depth: root -> stack -> layers -> layer -> tensor -> vector is 6 deep.
  // Newer files still verify (tables only grow), so the version check after
  // the verifier tells "update pleat" apart from "corrupt".
  flatbuffers::Verifier verifier(data, size, 32, 100000);
  if (!fb::VerifyModelBuffer(verifier)) r.bad("file is corrupt or truncated (FlatBuffers verifier)");
  const fb::Model& root = *fb::GetModel(data);
  if (root.format_version() > kModelFormatVersion)
    fail(PLEAT_ERROR_UNSUPPORTED_VERSION,
         "model '" + source + "' has format version " + std::to_string(root.format_version()) +
             "; this pleat reads up to " + std::to_string(kModelFormatVersion) + ": update pleat");
  if (root.format_version() == 0) r.bad("format_version is 0");

  auto m = std::make_shared<Model>();
  m->source = source;
  read_skeleton(r, root, m.get());
  m->frame_rate = root.frame_rate();
  m->window_frames = root.window_frames();
  const auto mode = static_cast<int32_t>(root.motion_mode());
  if (mode < 0 || mode > static_cast<int32_t>(fb::MotionMode::MAX))
    r.bad("motion_mode has unknown value " + std::to_string(mode));
  m->motion_mode = static_cast<MotionMode>(mode);
  m->default_top_k = root.default_top_k();

  m->body_features = r.features(root.body_features(), "body_features");
  m->body_normalization = r.normalization(root.body_normalization(), "body_normalization");
  m->body_encoder = r.mlp(r.need(root.body_encoder(), "body_encoder"), "body_encoder");
  m->body_pool = r.dense(r.need(root.body_pool(), "body_pool"), "body_pool", "body_pool");
  m->body_pool_activation = r.activation(root.body_pool_activation(), "body_pool_activation");
  m->body_vertex_stride = root.body_vertex_stride();
  if (m->body_vertex_stride > 1 && root.format_version() < 2)
    r.bad("body_vertex_stride " + std::to_string(m->body_vertex_stride) +
          " needs format_version 2 (the file says " + std::to_string(root.format_version()) + ")");
  m->garment_encoder = r.graph_stack(root.garment_encoder(), "garment_encoder");
  m->motion_features = r.features(root.motion_features(), "motion_features");
  m->motion_normalization = r.normalization(root.motion_normalization(), "motion_normalization");
  m->motion_encoder = r.gru(root.motion_encoder(), "motion_encoder");
  m->skinning = r.dense(r.need(root.skinning(), "skinning"), "skinning", "skinning");
  m->skinning_prior = root.skinning_prior();
  m->blend = r.graph_stack(root.blend(), "blend");
  m->blend_scale = root.blend_scale();
  m->refinement = r.graph_stack(root.refinement(), "refinement");
  m->refinement_scale = root.refinement_scale();
  m->offset_filter_length = root.offset_filter_length();
  if (m->offset_filter_length != 0.0f && root.format_version() < 3)
    r.bad("offset_filter_length " + std::to_string(m->offset_filter_length) +
          " needs format_version 3 (the file says " + std::to_string(root.format_version()) + ")");
  m->skinning_prior_radius = root.skinning_prior_radius();
  m->skinning_prior_floor = root.skinning_prior_floor();
  if ((m->skinning_prior_radius != 0.0f || m->skinning_prior_floor != kDefaultSkinningPriorFloor) &&
      root.format_version() < 4)
    r.bad("skinning_prior_radius " + std::to_string(m->skinning_prior_radius) + " and skinning_prior_floor " +
          std::to_string(m->skinning_prior_floor) + " need format_version 4 (the file says " +
          std::to_string(root.format_version()) + ")");
  read_metadata(r, root, m.get());
  validate_model(*m);
  return m;
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
