#include <cstring>

#include "capi/pleat.h"
#include "core/error.h"
#include "runtime/model_file.h"
#include "schema/model_generated.h"

// Reading model files: structure here (every field present, sized and
// within range), meaning in validate_model.

namespace pleat::runtime {
namespace fb = pleat::schema;

namespace {

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

}  // namespace

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
  if (refinement_reads_code(*m) && root.format_version() < 5)
    r.bad("refinement feature 'fused_code' needs format_version 5 (the file says " +
          std::to_string(root.format_version()) + ")");
  read_metadata(r, root, m.get());
  validate_model(*m);
  return m;
}

}  // namespace pleat::runtime
