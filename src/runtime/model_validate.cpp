// validate_model(): the semantic checks every model passes before an
// Instance may use it, whether it came from a file, the initialiser or a
// trainer. The nn layers' own validate()/prepare() run last, as a backstop,
// after the checks here have produced messages in model terms.
#include <cmath>
#include <set>

#include "capi/pleat.h"
#include "core/error.h"
#include "runtime/model.h"
#include "runtime/model_file.h"

namespace pleat::runtime {
namespace {

constexpr int32_t kMaxWindowFrames = 256;
constexpr double kMaxFrameRate = 1000.0;

class Checker {
 public:
  explicit Checker(const std::string& source) : prefix_("model '" + source + "': ") {}

  [[noreturn]] void bad(const std::string& what) const { fail(PLEAT_ERROR_FORMAT, prefix_ + what); }

  // The nn checks throw INVALID_ARGUMENT (right for callers that build
  // layers by hand); inside a model the same fault is a format error.
  template <typename F>
  void nn_check(const std::string& where, F&& fn) const {
    try {
      fn();
    } catch (const Error& e) {
      bad(where + ": " + e.what());
    }
  }

  void shape(const std::string& what, nn::Index rows, nn::Index cols, nn::Index expected_rows,
             nn::Index expected_cols) const {
    if (rows == expected_rows && cols == expected_cols) return;
    bad(what + " is " + std::to_string(rows) + "x" + std::to_string(cols) + ", expected " +
        std::to_string(expected_rows) + "x" + std::to_string(expected_cols));
  }

  void finite(double value, const std::string& what) const {
    if (!std::isfinite(value)) bad(what + " is not finite");
  }

 private:
  std::string prefix_;
};

std::string label(const std::string& stack, size_t i, const std::string& name) {
  return stack + " layer " + std::to_string(i) + " '" + name + "'";
}

void check_skeleton(const Checker& c, const Model& m) {
  const auto& names = m.skeleton.joint_names;
  const auto& parents = m.skeleton.parents;
  if (names.empty()) c.bad("skeleton has no joints");
  if (names.size() > static_cast<size_t>(kMaxModelJoints))
    c.bad("skeleton has " + std::to_string(names.size()) + " joints, at most " +
          std::to_string(kMaxModelJoints));
  if (parents.size() != names.size())
    c.bad("skeleton has " + std::to_string(names.size()) + " joint names but " +
          std::to_string(parents.size()) + " parents");
  std::set<std::string> seen;
  for (size_t j = 0; j < names.size(); ++j) {
    const std::string joint = "skeleton joint " + std::to_string(j) + " '" + names[j] + "'";
    if (names[j].empty()) c.bad("skeleton joint " + std::to_string(j) + " has an empty name");
    if (!seen.insert(names[j]).second) c.bad(joint + " is named twice");
    const int32_t p = parents[j];
    if (j == 0 ? p != -1 : (p < 0 || p >= static_cast<int32_t>(j)))
      c.bad(joint + " has parent " + std::to_string(p) +
            (j == 0 ? "; the first joint must be the root (-1)"
                    : "; parents must come first (a cycle or a second root)"));
  }
}

void check_shape_entries(const Checker& c, const Model& m) {
  if (m.shape.size() > static_cast<size_t>(kMaxModelShapeEntries))
    c.bad("shape has " + std::to_string(m.shape.size()) + " entries, at most " +
          std::to_string(kMaxModelShapeEntries));
  std::set<std::string> seen;
  for (size_t i = 0; i < m.shape.size(); ++i) {
    const std::string entry = "shape entry " + std::to_string(i) + " '" + m.shape[i].name + "'";
    if (m.shape[i].name.empty()) c.bad("shape entry " + std::to_string(i) + " has an empty name");
    if (!seen.insert(m.shape[i].name).second) c.bad(entry + " is named twice");
    c.finite(m.shape[i].default_value, entry + " default_value");
  }
}

void check_scalars(const Checker& c, const Model& m) {
  if (!(std::isfinite(m.frame_rate) && m.frame_rate > 0.0 && m.frame_rate <= kMaxFrameRate))
    c.bad("frame_rate is " + std::to_string(m.frame_rate) + ", expected a finite value in (0, 1000]");
  if (m.window_frames < 1 || m.window_frames > kMaxWindowFrames)
    c.bad("window_frames is " + std::to_string(m.window_frames) + ", expected 1.." +
          std::to_string(kMaxWindowFrames));
  if (m.motion_mode != MotionMode::window)
    c.bad("motion_mode has unknown value " + std::to_string(static_cast<int32_t>(m.motion_mode)));
  if (m.default_top_k < 1) c.bad("default_top_k is " + std::to_string(m.default_top_k) + ", expected >= 1");
  c.finite(m.blend_scale, "blend_scale");
  if (m.body_vertex_stride < 1 || m.body_vertex_stride > kMaxBodyVertexStride)
    c.bad("body_vertex_stride is " + std::to_string(m.body_vertex_stride) + ", expected 1.." +
          std::to_string(kMaxBodyVertexStride));
  if (!(std::isfinite(m.skinning_prior) && m.skinning_prior >= 0.0f))
    c.bad("skinning_prior is " + std::to_string(m.skinning_prior) + ", expected a finite value >= 0");
  if (!(std::isfinite(m.skinning_prior_radius) && m.skinning_prior_radius >= 0.0f &&
        m.skinning_prior_radius <= kMaxSkinningPriorRadius))
    c.bad("skinning_prior_radius is " + std::to_string(m.skinning_prior_radius) + ", expected 0.." +
          std::to_string(kMaxSkinningPriorRadius) + " m");
  if (!(std::isfinite(m.skinning_prior_floor) && m.skinning_prior_floor >= 1e-12f &&
        m.skinning_prior_floor <= 1.0f))
    c.bad("skinning_prior_floor is " + std::to_string(m.skinning_prior_floor) + ", expected 1e-12..1");
  c.finite(m.refinement_scale, "refinement_scale");
  if (!(std::isfinite(m.offset_filter_length) && m.offset_filter_length >= 0.0f &&
        m.offset_filter_length <= kMaxOffsetFilterLength))
    c.bad("offset_filter_length is " + std::to_string(m.offset_filter_length) + ", expected 0.." +
          std::to_string(kMaxOffsetFilterLength) + " m");
  const ModelBands& b = m.bands;
  if (!(b.low_fraction > 0.0 && b.low_fraction <= b.mid_fraction && b.mid_fraction <= 1.0))
    c.bad("bands fractions low " + std::to_string(b.low_fraction) + " / mid " +
          std::to_string(b.mid_fraction) + " must satisfy 0 < low <= mid <= 1");
  if (b.projection > PLEAT_PROJECTION_SYMMETRIC)
    c.bad("bands projection has unknown value " + std::to_string(b.projection));
}

// Input width of a feature list after checking each entry is known, allowed
// for this stack and listed once.
nn::Index check_features(const Checker& c, const Model& m, const std::vector<Feature>& features,
                         const std::set<Feature>& allowed, const std::string& what) {
  if (features.size() > static_cast<size_t>(kMaxStackFeatures))
    c.bad(what + " lists " + std::to_string(features.size()) + " features, at most " +
          std::to_string(kMaxStackFeatures));
  std::set<Feature> seen;
  nn::Index width = 0;
  for (size_t i = 0; i < features.size(); ++i) {
    const auto value = static_cast<int32_t>(features[i]);
    if (value < 0 || value > static_cast<int32_t>(Feature::fused_code))
      c.bad(what + " entry " + std::to_string(i) + " is unknown feature " + std::to_string(value));
    if (!allowed.count(features[i]))
      c.bad(what + " entry " + std::to_string(i) + " '" + feature_name(features[i]) +
            "' is not an input of this stack");
    if (!seen.insert(features[i]).second) c.bad(what + " lists '" + feature_name(features[i]) + "' twice");
    width +=
        feature_width(features[i], m.joint_count(), m.shape_count(), static_cast<int32_t>(m.code_width()));
  }
  return width;
}

void check_normalization(const Checker& c, const InputNormalization& n, nn::Index width,
                         const std::string& what) {
  if (n.empty()) return;
  if (n.shift.size() != width || n.scale.size() != width)
    c.bad(what + " has " + std::to_string(n.shift.size()) + " shift and " + std::to_string(n.scale.size()) +
          " scale values, expected " + std::to_string(width) + " each (the stack's input width) or none");
}

void check_activation(const Checker& c, const nn::Activation& a, const std::string& what) {
  const auto kind = static_cast<int32_t>(a.kind);
  if (kind < 0 || kind > static_cast<int32_t>(nn::ActivationKind::elu))
    c.bad(what + " has unknown kind " + std::to_string(kind));
  c.finite(a.parameter, what + " parameter");
}

void check_dense(const Checker& c, const nn::Dense& d, const std::string& what, nn::Index in, nn::Index out) {
  c.shape(what + " weight", d.weight.rows(), d.weight.cols(), in, out < 0 ? d.weight.cols() : out);
  if (d.bias.size() != 0 && d.bias.size() != d.weight.cols())
    c.bad(what + " bias has " + std::to_string(d.bias.size()) + " values, expected " +
          std::to_string(d.weight.cols()));
  c.nn_check(what, [&] { d.validate(); });
}

void check_mlp(const Checker& c, const nn::Mlp& mlp, const std::string& what, nn::Index in) {
  if (mlp.layers.empty()) c.bad(what + " has no layers");
  check_activation(c, mlp.hidden_activation, what + " hidden_activation");
  check_activation(c, mlp.output_activation, what + " output_activation");
  nn::Index width = in;
  for (size_t i = 0; i < mlp.layers.size(); ++i) {
    check_dense(c, mlp.layers[i], label(what, i, mlp.layers[i].name), width, -1);
    width = mlp.layers[i].out_width();
  }
  c.nn_check(what, [&] { mlp.validate(); });
}

// Chains the layers from `in` to `out` and prepares them.
void check_graph_stack(const Checker& c, GraphStack& stack, const std::string& what, nn::Index in,
                       nn::Index out) {
  if (stack.layers.empty()) c.bad(what + " has no layers");
  nn::Index width = in;
  for (size_t i = 0; i < stack.layers.size(); ++i) {
    nn::GraphAttentionLayer& l = stack.layers[i];
    const std::string at = label(what, i, l.name);
    const auto variant = static_cast<int32_t>(l.variant);
    const auto merge = static_cast<int32_t>(l.merge);
    if (variant < 0 || variant > static_cast<int32_t>(nn::AttentionVariant::flexigat))
      c.bad(at + " variant has unknown value " + std::to_string(variant));
    if (merge < 0 || merge > static_cast<int32_t>(nn::HeadMerge::mean))
      c.bad(at + " merge has unknown value " + std::to_string(merge));
    if (l.heads < 1 || l.heads > nn::kMaxAttentionHeads)
      c.bad(at + " heads is " + std::to_string(l.heads) + ", expected 1.." +
            std::to_string(nn::kMaxAttentionHeads));
    check_activation(c, l.activation, at + " activation");
    const bool last = i + 1 == stack.layers.size();
    const nn::Index cols =
        !last ? l.weight.cols()
              : (l.merge == nn::HeadMerge::concat ? out : static_cast<nn::Index>(l.heads) * out);
    c.shape(at + " weight", l.weight.rows(), l.weight.cols(), width, cols);
    if (l.weight.cols() % l.heads != 0)
      c.bad(at + " weight has " + std::to_string(l.weight.cols()) + " columns, not a multiple of its " +
            std::to_string(l.heads) + " heads");
    c.shape(at + " attention", l.attention.rows(), l.attention.cols(), l.heads, 2 * l.head_width());
    const bool flexible = l.variant == nn::AttentionVariant::flexigat;
    for (const auto* v : {&l.p, &l.q})
      if ((flexible || v->size() != 0) && v->size() != l.heads)
        c.bad(at + (v == &l.p ? " p" : " q") + " has " + std::to_string(v->size()) + " values, expected " +
              std::to_string(l.heads) + " (one per head)");
    if (l.bias.size() != 0 && l.bias.size() != l.out_width())
      c.bad(at + " bias has " + std::to_string(l.bias.size()) + " values, expected " +
            std::to_string(l.out_width()));
    c.finite(l.negative_slope, at + " negative_slope");
    if (!(std::isfinite(l.lipschitz_epsilon) && l.lipschitz_epsilon > 0.0f))
      c.bad(at + " lipschitz_epsilon is " + std::to_string(l.lipschitz_epsilon) +
            ", expected a finite value > 0");
    c.nn_check(at, [&] { l.prepare(); });
    width = l.out_width();
  }
}

void check_gru(const Checker& c, const nn::Gru& gru, nn::Index in, nn::Index hidden) {
  const std::string what = "motion_encoder";
  if (gru.layers.empty()) c.bad(what + " has no layers");
  for (size_t i = 0; i < gru.layers.size(); ++i) {
    const nn::GruLayer& l = gru.layers[i];
    const std::string at = what + " layer " + std::to_string(i);
    c.shape(at + " w_ih", l.w_ih.rows(), l.w_ih.cols(), i == 0 ? in : hidden, 3 * hidden);
    c.shape(at + " w_hh", l.w_hh.rows(), l.w_hh.cols(), hidden, 3 * hidden);
    c.shape(at + " b_ih", 1, l.b_ih.size(), 1, 3 * hidden);
    c.shape(at + " b_hh", 1, l.b_hh.size(), 1, 3 * hidden);
  }
  c.nn_check(what, [&] { gru.validate(); });
}

}  // namespace

void validate_model(Model& m) {
  const Checker c(m.source);
  check_skeleton(c, m);
  check_shape_entries(c, m);
  check_scalars(c, m);
  for (const TensorView& t : model_tensors(m))
    if (!Eigen::Map<const Eigen::ArrayXf>(t.data, static_cast<nn::Index>(t.size())).allFinite())
      c.bad(t.name + " holds a NaN or infinite value");

  const nn::Index body_in =
      check_features(c, m, m.body_features, {Feature::shape, Feature::rest_joint_distances}, "body_features");
  const nn::Index garment_in =
      check_features(c, m, m.garment_encoder.features,
                     {Feature::rest_position, Feature::rest_normal, Feature::rest_joint_distances},
                     "garment_encoder features");
  const nn::Index motion_in = check_features(
      c, m, m.motion_features, {Feature::joint_rotations_6d, Feature::root_velocity}, "motion_features");
  const nn::Index refinement_in = check_features(
      c, m, m.refinement.features,
      {Feature::velocity, Feature::normal, Feature::posed_joint_distances, Feature::fused_code},
      "refinement features");
  // The blend stack reads the fused code F, not raw features.
  if (!m.blend.features.empty()) c.bad("blend features must be empty (the blend stack reads the fused code)");
  if (!m.blend.normalization.empty())
    c.bad("blend normalization must be empty (the blend stack reads the fused code)");
  const std::pair<nn::Index, const char*> inputs[] = {{body_in, "body_features"},
                                                      {garment_in, "garment_encoder features"},
                                                      {motion_in, "motion_features"},
                                                      {refinement_in, "refinement features"}};
  for (const auto& [width, what] : inputs)
    if (width < 1) c.bad(std::string(what) + " give no input columns");

  check_normalization(c, m.body_normalization, body_in, "body_normalization");
  check_normalization(c, m.garment_encoder.normalization, garment_in, "garment_encoder normalization");
  check_normalization(c, m.motion_normalization, motion_in, "motion_normalization");
  check_normalization(c, m.refinement.normalization, refinement_in, "refinement normalization");

  check_mlp(c, m.body_encoder, "body_encoder", body_in);
  check_dense(c, m.body_pool, "body_pool", 2 * m.body_encoder.out_width(), -1);
  check_activation(c, m.body_pool_activation, "body_pool_activation");
  const nn::Index code = m.code_width();
  if (code < 1) c.bad("code width (body_pool output) is 0");
  check_graph_stack(c, m.garment_encoder, "garment_encoder", garment_in, code);
  check_gru(c, m.motion_encoder, motion_in, code);
  check_dense(c, m.skinning, "skinning", code, m.joint_count());
  check_graph_stack(c, m.blend, "blend", code, 3);
  check_graph_stack(c, m.refinement, "refinement", refinement_in, 3);
}

}  // namespace pleat::runtime
