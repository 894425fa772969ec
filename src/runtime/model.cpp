#include "runtime/model.h"

#include <algorithm>

namespace pleat::runtime {

int32_t feature_width(Feature feature, int32_t joint_count, int32_t shape_count, int32_t code_width) {
  switch (feature) {
    case Feature::shape: return shape_count;
    case Feature::rest_joint_distances:
    case Feature::posed_joint_distances: return joint_count;
    case Feature::joint_rotations_6d: return 6 * joint_count;
    case Feature::rest_position:
    case Feature::rest_normal:
    case Feature::root_velocity:
    case Feature::velocity:
    case Feature::normal: return 3;
    case Feature::fused_code: return code_width;
  }
  return -1;
}

const char* feature_name(Feature feature) {
  switch (feature) {
    case Feature::shape: return "shape";
    case Feature::rest_joint_distances: return "rest_joint_distances";
    case Feature::rest_position: return "rest_position";
    case Feature::rest_normal: return "rest_normal";
    case Feature::joint_rotations_6d: return "joint_rotations_6d";
    case Feature::root_velocity: return "root_velocity";
    case Feature::velocity: return "velocity";
    case Feature::normal: return "normal";
    case Feature::posed_joint_distances: return "posed_joint_distances";
    case Feature::fused_code: return "fused_code";
  }
  return "unknown";
}

bool refinement_reads_code(const Model& model) {
  const std::vector<Feature>& f = model.refinement.features;
  return std::find(f.begin(), f.end(), Feature::fused_code) != f.end();
}

int64_t parameter_count(const Model& model) {
  int64_t count = 0;
  const auto dense = [&](const nn::Dense& d) { count += d.weight.size() + d.bias.size(); };
  const auto stack = [&](const GraphStack& g) {
    for (const nn::GraphAttentionLayer& l : g.layers)
      count += l.weight.size() + l.attention.size() + l.p.size() + l.q.size() + l.bias.size();
  };
  for (const nn::Dense& d : model.body_encoder.layers) dense(d);
  dense(model.body_pool);
  stack(model.garment_encoder);
  for (const nn::GruLayer& l : model.motion_encoder.layers)
    count += l.w_ih.size() + l.w_hh.size() + l.b_ih.size() + l.b_hh.size();
  dense(model.skinning);
  stack(model.blend);
  stack(model.refinement);
  return count;
}

}  // namespace pleat::runtime
