#include "runtime/binding.h"

#include <algorithm>
#include <memory>

#include "capi/pleat.h"
#include "core/box_tree.h"
#include "core/error.h"
#include "core/nearest_points.h"
#include "runtime/frame_features.h"

namespace pleat::runtime {
namespace {

[[noreturn]] void bad_binding(const std::string& what) {
  fail(PLEAT_ERROR_INVALID_ARGUMENT, what);
}

// Model joint j is body joint body_of_model[j]: same count, every model
// name present, parents corresponding. Messages name the joint at fault.
std::vector<int32_t> map_joints(const Model& model, const Skeleton& body, const std::string& body_source) {
  const ModelSkeleton& s = model.skeleton;
  if (body.joint_count() != s.joint_count())
    bad_binding("body '" + body_source + "' has " + std::to_string(body.joint_count()) + " joints, model '" +
                model.source + "' was trained on " + std::to_string(s.joint_count()) +
                " (retarget the motion onto a body with the model's skeleton)");
  std::vector<int32_t> map(static_cast<size_t>(s.joint_count()));
  for (int32_t j = 0; j < s.joint_count(); ++j) {
    const int32_t b = body.find(s.joint_names[j]);
    if (b < 0)
      bad_binding("model joint " + std::to_string(j) + " '" + s.joint_names[j] +
                  "' is not a joint of body '" + body_source + "'");
    map[j] = b;
  }
  for (int32_t j = 0; j < s.joint_count(); ++j) {
    const int32_t model_parent = s.parents[j];
    const int32_t body_parent = body.parents[map[j]];
    const int32_t expected = model_parent < 0 ? -1 : map[model_parent];
    if (body_parent != expected)
      bad_binding("joint '" + s.joint_names[j] + "' has parent '" +
                  (body_parent < 0 ? std::string("(none)") : body.names[body_parent]) + "' in body '" +
                  body_source + "' but '" +
                  (model_parent < 0 ? std::string("(none)") : s.joint_names[model_parent]) + "' in model '" +
                  model.source + "'");
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
      bad_binding("model '" + model.source + "' reads shape entry '" + entry.name + "', which body '" +
                  body.source + "' does not have");
    beta[i] = static_cast<float>(it->value);
  }
  return beta;
}

// The body's skin weights seen from each rest garment vertex (N x S, model
// joint order): the mean over the rest body vertices within `radius`,
// weighted 1 - (d / radius)², or the nearest vertex's weights where none is
// that close (and everywhere for radius 0).
nn::MatrixRM prior_weights(const Body& body, const Points3d& garment, double radius,
                           const std::vector<int32_t>& model_of_body) {
  const Points3d& points = body.rest.vertices;
  const SkinWeights& w = body.weights;
  const std::vector<int32_t> nearest = nearest_points(points, garment);
  nn::MatrixRM prior = nn::MatrixRM::Zero(garment.rows(), static_cast<Eigen::Index>(model_of_body.size()));
  const auto add = [&](Eigen::Index v, int32_t b, double share) {
    for (int32_t k = w.offsets[b]; k < w.offsets[b + 1]; ++k)
      prior(v, model_of_body[w.joints[k]]) += static_cast<float>(share * w.weights[k]);
  };
  std::unique_ptr<BoxTree> tree;
  if (radius > 0.0) {
    std::vector<Box> boxes(static_cast<size_t>(points.rows()));
    for (Eigen::Index b = 0; b < points.rows(); ++b)
      boxes[static_cast<size_t>(b)].extend(points.row(b).transpose());
    tree = std::make_unique<BoxTree>(std::move(boxes));
  }
  std::vector<std::pair<int32_t, double>> near;
  for (Eigen::Index v = 0; v < garment.rows(); ++v) {
    near.clear();
    double total = 0.0;
    if (tree) {
      const Eigen::Vector3d x = garment.row(v).transpose();
      Box query;
      query.extend(x);
      query.inflate(radius);
      tree->query(query, [&](int32_t b) {
        const double d2 = (points.row(b).transpose() - x).squaredNorm() / (radius * radius);
        if (d2 < 1.0) near.emplace_back(b, 1.0 - d2), total += 1.0 - d2;
      });
    }
    if (near.empty()) {
      add(v, nearest[static_cast<size_t>(v)], 1.0);
      continue;
    }
    for (const auto& [b, k] : near) add(v, b, k / total);
  }
  return prior;
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
  b->model_of_body.resize(b->body_of_model.size());
  for (size_t j = 0; j < b->body_of_model.size(); ++j)
    b->model_of_body[static_cast<size_t>(b->body_of_model[j])] = static_cast<int32_t>(j);
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

  // Skinning prior: the body's weights around each rest garment vertex.
  if (m.skinning_prior > 0.0f) {
    b->prior = prior_weights(body, g.rest.vertices, m.skinning_prior_radius, b->model_of_body);
    b->prior = m.skinning_prior * (b->prior.array() + m.skinning_prior_floor).log();
  }
  b->graph = nn::attention_graph(g.graph);
  b->rest = g.rest.vertices.cast<float>();
  if (m.offset_filter_length > 0.0f)
    b->offset_filter = std::make_unique<OffsetFilter>(g, m.offset_filter_length);
  return b;
}

}  // namespace pleat::runtime
