#include "runtime/model_init.h"

#include <cmath>
#include <random>

#include "capi/pleat.h"
#include "core/error.h"
#include "runtime/model_file.h"

namespace pleat::runtime {
namespace {

constexpr int32_t kMaxInitWidth = 4096;
constexpr double kPi = 3.14159265358979323846;

// std::mt19937_64's output sequence is fixed by the standard; the
// distributions of <random> are not, so uniform and normal numbers are
// mapped here.
class Random {
 public:
  explicit Random(uint64_t seed) : engine_(seed) {}

  // [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

  // Box-Muller; both values of a pair are used.
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]: log stays finite
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * kPi * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * kPi * u2);
  }

  template <typename M>
  void fill_normal(M& m, double mean, double stddev) {
    for (nn::Index i = 0; i < m.size(); ++i) m.data()[i] = static_cast<float>(mean + stddev * normal());
  }
  template <typename M>
  void fill_uniform(M& m, double bound) {
    for (nn::Index i = 0; i < m.size(); ++i)
      m.data()[i] = static_cast<float>(bound * (2.0 * uniform() - 1.0));
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

[[noreturn]] void bad_option(const std::string& what) {
  fail(PLEAT_ERROR_INVALID_ARGUMENT, "initialize_model: " + what);
}

void check_widths(const std::vector<int32_t>& widths, const char* what, int32_t heads, int32_t last) {
  if (widths.empty() || widths.size() > 64) bad_option(std::string(what) + " must list 1..64 widths");
  for (size_t i = 0; i < widths.size(); ++i) {
    if (widths[i] < 1 || widths[i] > kMaxInitWidth)
      bad_option(std::string(what) + "[" + std::to_string(i) + "] is " + std::to_string(widths[i]) +
                 ", expected 1.." + std::to_string(kMaxInitWidth));
    // Hidden graph layers concatenate heads of width/heads each.
    if (heads > 0 && i + 1 < widths.size() && widths[i] % heads != 0)
      bad_option(std::string(what) + "[" + std::to_string(i) + "] = " + std::to_string(widths[i]) +
                 " is not a multiple of the " + std::to_string(heads) + " heads");
  }
  if (last > 0 && widths.back() != last)
    bad_option(std::string(what) + " must end in " + std::to_string(last) + ", ends in " +
               std::to_string(widths.back()));
}

// Geometric initialisation (Atzmon & Lipman, SAL), hidden-layer rule:
// W ~ N(0, sqrt(2 / out)), b = 0. Used for every linear layer that produces
// a code (body encoder, body pool): their outputs must start diverse.
nn::Dense sal_hidden(Random& rng, const std::string& name, nn::Index in, nn::Index out) {
  nn::Dense d;
  d.name = name;
  d.weight.resize(in, out);
  rng.fill_normal(d.weight, 0.0, std::sqrt(2.0 / static_cast<double>(out)));
  d.bias = nn::RowVector::Zero(out);
  return d;
}

// SAL's last-layer rule, W ~ N(sqrt(pi / in), 1e-4), for the softmax
// skinning head. SAL's bias -r places the zero level set of an SDF on a
// sphere of radius r; a softmax has no such level set and adding one
// constant to every logit of a row changes nothing, so the bias is 0. The
// common mean of W likewise cancels in the softmax: the head starts at
// uniform weights 1/S (up to 1e-4 noise) and the data, not the noise,
// decides which joints a vertex follows.
nn::Dense sal_softmax_head(Random& rng, const std::string& name, nn::Index in, nn::Index out) {
  nn::Dense d;
  d.name = name;
  d.weight.resize(in, out);
  rng.fill_normal(d.weight, std::sqrt(kPi / static_cast<double>(in)), 1e-4);
  d.bias = nn::RowVector::Zero(out);
  return d;
}

// Kaiming normal, fan_in mode, gain sqrt(2) (PyTorch's kaiming_normal_
// default): W ~ N(0, sqrt(2 / in)). Each attention vector a_h is a linear map
// of the 2d' values [z_i | z_j], so its fan_in is 2d'. P = Q = 1 (plain GAT at
// the start, DESIGN §4), bias 0.
GraphStack graph_stack(Random& rng, const std::string& name, const std::vector<Feature>& features,
                       nn::Index in, const std::vector<int32_t>& widths, const ModelInitOptions& o,
                       nn::Activation last) {
  GraphStack stack;
  stack.features = features;
  for (size_t i = 0; i < widths.size(); ++i) {
    const bool is_last = i + 1 == widths.size();
    nn::GraphAttentionLayer l;
    l.name = name + "." + std::to_string(i);
    l.variant = o.variant;
    l.merge = is_last ? nn::HeadMerge::mean : nn::HeadMerge::concat;
    l.activation = is_last ? last : nn::Activation::tanh();
    l.heads = o.heads;
    const nn::Index head_width = is_last ? widths[i] : widths[i] / o.heads;
    l.weight.resize(in, o.heads * head_width);
    rng.fill_normal(l.weight, 0.0, std::sqrt(2.0 / static_cast<double>(in)));
    l.attention.resize(o.heads, 2 * head_width);
    rng.fill_normal(l.attention, 0.0, std::sqrt(2.0 / static_cast<double>(2 * head_width)));
    l.p = nn::RowVector::Ones(o.heads);
    l.q = nn::RowVector::Ones(o.heads);
    l.bias = nn::RowVector::Zero(widths[i]);
    in = l.out_width();
    stack.layers.push_back(std::move(l));
  }
  return stack;
}

nn::Index input_width(const std::vector<Feature>& features, const ModelSkeleton& s,
                      const std::vector<ShapeEntry>& shape, int32_t code_width) {
  nn::Index w = 0;
  for (Feature f : features)
    w += feature_width(f, s.joint_count(), static_cast<int32_t>(shape.size()), code_width);
  return w;
}

}  // namespace

std::shared_ptr<Model> initialize_model(const ModelSkeleton& skeleton, const std::vector<ShapeEntry>& shape,
                                        const ModelInitOptions& o) {
  if (o.heads < 1 || o.heads > nn::kMaxAttentionHeads)
    bad_option("heads is " + std::to_string(o.heads) + ", expected 1.." +
               std::to_string(nn::kMaxAttentionHeads));
  if (o.code_width < 1 || o.code_width > kMaxInitWidth)
    bad_option("code_width is " + std::to_string(o.code_width) + ", expected 1.." +
               std::to_string(kMaxInitWidth));
  if (o.gru_layers < 1 || o.gru_layers > 64)
    bad_option("gru_layers is " + std::to_string(o.gru_layers) + ", expected 1..64");
  check_widths(o.body_widths, "body_widths", 0, 0);
  if (o.body_vertex_stride < 1 || o.body_vertex_stride > kMaxBodyVertexStride)
    bad_option("body_vertex_stride is " + std::to_string(o.body_vertex_stride) + ", expected 1.." +
               std::to_string(kMaxBodyVertexStride));
  if (!(o.offset_filter_length >= 0.0f && o.offset_filter_length <= kMaxOffsetFilterLength))
    bad_option("offset_filter_length is " + std::to_string(o.offset_filter_length) + ", expected 0.." +
               std::to_string(kMaxOffsetFilterLength) + " m");
  check_widths(o.garment_widths, "garment_widths", o.heads, o.code_width);
  check_widths(o.blend_widths, "blend_widths", o.heads, 3);
  check_widths(o.refinement_widths, "refinement_widths", o.heads, 3);
  // Widths derive from the joint count: refuse absurd skeletons before sizing.
  if (skeleton.joint_names.size() > 1024 || shape.size() > 1024)
    bad_option("skeleton or shape vector too large (at most 1024 joints and 1024 shape entries)");

  auto m = std::make_shared<Model>();
  m->source = "initialised (seed " + std::to_string(o.seed) + ")";
  m->skeleton = skeleton;
  m->shape = shape;
  m->frame_rate = o.frame_rate;
  m->window_frames = o.window_frames;
  m->default_top_k = o.default_top_k;
  m->blend_scale = o.blend_scale;
  m->refinement_scale = o.refinement_scale;
  m->skinning_prior = o.skinning_prior;
  m->skinning_prior_radius = o.skinning_prior_radius;
  m->skinning_prior_floor = o.skinning_prior_floor;
  m->body_vertex_stride = o.body_vertex_stride;
  m->offset_filter_length = o.offset_filter_length;
  m->body_features = {Feature::shape, Feature::rest_joint_distances};
  m->motion_features = {Feature::joint_rotations_6d, Feature::root_velocity};

  Random rng(o.seed);
  // Body encoder: tanh throughout (its output is pooled into a code).
  m->body_encoder.name = "body_encoder";
  m->body_encoder.hidden_activation = nn::Activation::tanh();
  m->body_encoder.output_activation = nn::Activation::tanh();
  nn::Index in = input_width(m->body_features, skeleton, shape, o.code_width);
  for (size_t i = 0; i < o.body_widths.size(); ++i) {
    m->body_encoder.layers.push_back(
        sal_hidden(rng, "body_encoder." + std::to_string(i), in, o.body_widths[i]));
    in = o.body_widths[i];
  }
  m->body_pool = sal_hidden(rng, "body_pool", 2 * in, o.code_width);

  m->garment_encoder = graph_stack(
      rng, "garment_encoder", {Feature::rest_position, Feature::rest_normal, Feature::rest_joint_distances},
      input_width({Feature::rest_position, Feature::rest_normal, Feature::rest_joint_distances}, skeleton,
                  shape, o.code_width),
      o.garment_widths, o, nn::Activation::tanh());

  // torch.nn.GRU's default: every weight and bias ~ U(-1/sqrt(H), 1/sqrt(H)).
  m->motion_encoder.name = "motion_encoder";
  const nn::Index h = o.code_width;
  const double bound = 1.0 / std::sqrt(static_cast<double>(h));
  in = input_width(m->motion_features, skeleton, shape, o.code_width);
  for (int32_t l = 0; l < o.gru_layers; ++l) {
    nn::GruLayer layer;
    layer.w_ih.resize(l == 0 ? in : h, 3 * h);
    layer.w_hh.resize(h, 3 * h);
    layer.b_ih.resize(3 * h);
    layer.b_hh.resize(3 * h);
    rng.fill_uniform(layer.w_ih, bound);
    rng.fill_uniform(layer.w_hh, bound);
    rng.fill_uniform(layer.b_ih, bound);
    rng.fill_uniform(layer.b_hh, bound);
    m->motion_encoder.layers.push_back(std::move(layer));
  }

  m->skinning = sal_softmax_head(rng, "skinning", o.code_width, skeleton.joint_count());
  m->blend = graph_stack(rng, "blend", {}, o.code_width, o.blend_widths, o, nn::Activation::identity());
  if (o.refinement_features.empty()) bad_option("refinement_features is empty");
  m->refinement = graph_stack(rng, "refinement", o.refinement_features,
                              input_width(o.refinement_features, skeleton, shape, o.code_width),
                              o.refinement_widths, o, nn::Activation::identity());

  TrainingInfo& t = m->training;
  t.dataset = "none (initialised)";
  t.generator = "pleat " PLEAT_VERSION_STRING " initialiser";
  t.seed = static_cast<int64_t>(o.seed);
  t.created = o.created;

  // A bad skeleton, shape entry or scalar option is the caller's argument,
  // not a file's format.
  try {
    validate_model(*m);
  } catch (const Error& e) {
    fail(PLEAT_ERROR_INVALID_ARGUMENT, std::string("initialize_model: ") + e.what());
  }
  return m;
}

}  // namespace pleat::runtime
