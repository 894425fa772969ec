#pragma once
// Small internal-library fixtures shared by the runtime and trainer tests: a
// three-joint chain body (hips -> spine -> arm, identity rest rotations) and
// a strip-shaped attention graph.
#include "body/body.h"
#include "nn/graph_attention.h"

namespace pleat_test {

// Joints at (0, 1, 0), (0, 1.3, 0), (0.3, 1.4, 0); four vertices in front of
// them, skinned to hips, hips, hips/spine, arm.
inline pleat::Body chain_body() {
  pleat::Body b;
  b.source = "chain";
  b.skeleton.names = {"hips", "spine", "arm"};
  b.skeleton.parents = {-1, 0, 1};
  b.skeleton.rest_translation.resize(3, 3);
  b.skeleton.rest_translation << 0, 1, 0, 0, 0.3, 0, 0.3, 0.1, 0;
  b.skeleton.rest_rotation.assign(3, Eigen::Quaterniond::Identity());
  b.rest.vertices.resize(4, 3);
  b.rest.vertices << -0.1, 0.9, 0.1, 0.1, 0.9, 0.1, 0, 1.3, 0.1, 0.3, 1.4, 0.1;
  b.rest.triangles.resize(2, 3);
  b.rest.triangles << 0, 1, 2, 1, 3, 2;
  b.weights.joint_count = 3;
  b.weights.offsets = {0, 1, 2, 4, 5};
  b.weights.joints = {0, 0, 0, 1, 2};
  b.weights.weights = {1, 1, 0.5, 0.5, 1};
  return b;
}

// n nodes, each linked to the two before and after it, except the last,
// which is isolated (self loop only).
inline pleat::nn::AttentionGraph strip_graph(int n) {
  pleat::Csr csr;
  csr.offsets = {0};
  for (int v = 0; v < n; ++v) {
    for (int u : {v - 2, v - 1, v + 1, v + 2})
      if (u >= 0 && u < n - 1 && v < n - 1) csr.indices.push_back(u);
    csr.offsets.push_back(static_cast<int32_t>(csr.indices.size()));
  }
  return pleat::nn::attention_graph(csr);
}

}  // namespace pleat_test
