#include "runtime/binding.h"

#include <algorithm>

#include "capi/pleat.h"
#include "core/error.h"
#include "metrics/nearest_points.h"
#include "runtime/frame_features.h"

namespace pleat::runtime {
namespace {

[[noreturn]] void bad(const std::string& what) {
  fail(PLEAT_ERROR_INVALID_ARGUMENT, what);
}

// Model joint j is body joint body_of_model[j]: same count, every model
// name present, parents corresponding. Messages name the joint at fault.
std::vector<int32_t> map_joints(const Model& model, const Skeleton& body, const std::string& body_source) {
  const ModelSkeleton& s = model.skeleton;
  if (body.joint_count() != s.joint_count())
    bad("body '" + body_source + "' has " + std::to_string(body.joint_count()) + " joints, model '" +
        model.source + "' was trained on " + std::to_string(s.joint_count()) +
        " (retarget the motion onto a body with the model's skeleton)");
  std::vector<int32_t> map(static_cast<size_t>(s.joint_count()));
  for (int32_t j = 0; j < s.joint_count(); ++j) {
    const int32_t b = body.find(s.joint_names[j]);
    if (b < 0)
      bad("model joint " + std::to_string(j) + " '" + s.joint_names[j] + "' is not a joint of body '" +
          body_source + "'");
    map[j] = b;
  }
  for (int32_t j = 0; j < s.joint_count(); ++j) {
    const int32_t model_parent = s.parents[j];
    const int32_t body_parent = body.parents[map[j]];
    const int32_t expected = model_parent < 0 ? -1 : map[model_parent];
    if (body_parent != expected)
      bad("joint '" + s.joint_names[j] + "' has parent '" +
          (body_parent < 0 ? std::string("(none)") : body.names[body_parent]) + "' in body '" + body_source +
          "' but '" + (model_parent < 0 ? std::string("(none)") : s.joint_names[model_parent]) +
          "' in model '" + model.source + "'");
  }
  return map;
}

// β in the model's order: the body's value by name, the model's default for
// a body without a shape vector.
nn::RowVector shape_vector(const Model& model, const Body& body) {
  nn::RowVector beta(model.shape_count());
  for (int32_t i = 0; i < model.shape_count(); ++i) {
    const ShapeEntry& entry = model.shape[i];
    if (body.shape.empty()) {
      beta[i] = entry.default_value;
      continue;
    }
    const auto it = std::find_if(body.shape.begin(), body.shape.end(),
                                 [&](const ShapeParameter& p) { return p.name == entry.name; });
    if (it == body.shape.end())
      bad("model '" + model.source + "' reads shape entry '" + entry.name + "', which body '" + body.source +
          "' does not have");
    beta[i] = static_cast<float>(it->value);
  }
  return beta;
}

}  // namespace

void normalize_rows(const InputNormalization& n, nn::MatrixRM& x, int32_t begin, int32_t end) {
  if (n.empty()) return;
  for (int32_t r = begin; r < end; ++r) x.row(r) = (x.row(r) - n.shift).cwiseProduct(n.scale);
}

std::unique_ptr<Binding> bind_inputs(const Model& m, const Garment& g, const Body& body) {
  auto b = std::make_unique<Binding>();
  const int32_t joints = m.joint_count(), n = g.rest.vertex_count();
  b->body_of_model = map_joints(m, body.skeleton, body.source);
  b->skeleton = body.skeleton;
  b->rest_global = rest_transforms(b->skeleton);
  b->rest_joints.resize(joints, 3);
  for (int32_t j = 0; j < joints; ++j)
    b->rest_joints.row(j) = b->rest_global[b->body_of_model[j]].translation().transpose();

  // Body encoder input: per body vertex 0, k, 2k, ... [β | distances to J(β)].
  const nn::RowVector beta = shape_vector(m, body);
  const int32_t stride = m.body_vertex_stride;
  const int32_t nb = (body.vertex_count() + stride - 1) / stride;
  b->body_input.resize(nb, m.body_encoder.in_width());
  for (int32_t row = 0; row < nb; ++row) {
    const int32_t v = row * stride;
    Index col = 0;
    for (Feature f : m.body_features) {
      if (f == Feature::shape) {
        b->body_input.row(row).segment(col, beta.size()) = beta;
        col += beta.size();
      } else {  // rest_joint_distances
        for (int32_t j = 0; j < joints; ++j)
          b->body_input(row, col + j) =
              static_cast<float>((body.rest.vertices.row(v) - b->rest_joints.row(j)).norm());
        col += joints;
      }
    }
  }
  normalize_rows(m.body_normalization, b->body_input, 0, nb);

  // Garment encoder input.
  b->garment_input.resize(n, m.garment_encoder.in_width());
  FrameFeatures(m, b->skeleton, b->body_of_model).rest_garment(g, b->rest_joints, b->garment_input);
  normalize_rows(m.garment_encoder.normalization, b->garment_input, 0, n);

  // Skinning prior: the weights of the nearest rest body vertex.
  if (m.skinning_prior > 0.0f) {
    const std::vector<int32_t> nearest = nearest_points(body.rest.vertices, g.rest.vertices);
    std::vector<int32_t> model_of_body(static_cast<size_t>(joints));
    for (int32_t j = 0; j < joints; ++j) model_of_body[b->body_of_model[j]] = j;
    b->prior = nn::MatrixRM::Zero(n, joints);
    for (int32_t v = 0; v < n; ++v) {
      const int32_t near = nearest[v];
      for (int32_t k = body.weights.offsets[near]; k < body.weights.offsets[near + 1]; ++k)
        b->prior(v, model_of_body[body.weights.joints[k]]) = static_cast<float>(body.weights.weights[k]);
    }
    b->prior = m.skinning_prior * (b->prior.array() + kSkinningPriorFloor).log();
  }
  b->graph = nn::attention_graph(g.graph);
  b->rest = g.rest.vertices.cast<float>();
  if (m.offset_filter_length > 0.0f)
    b->offset_filter = std::make_unique<OffsetFilter>(g, m.offset_filter_length);
  return b;
}

}  // namespace pleat::runtime
