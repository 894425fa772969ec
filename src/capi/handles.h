#pragma once
// What the opaque C handles are.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "body/body.h"
#include "body/skeleton.h"
#include "garment/garment.h"
#include "runtime/instance.h"
#include "runtime/model.h"

// The garment itself is immutable and shared with the instances bound to it;
// pleat_garment_prepare swaps in a prepared copy, so an instance keeps the
// garment it was bound to even after the handle is destroyed or re-prepared.
struct pleat_garment {
  std::shared_ptr<const pleat::Garment> garment;
};

struct pleat_body {
  pleat::Body body;
  // Rebuilds the body for a shape vector; empty for fixed-shape bodies
  // (rigged meshes). Shares the immutable model data (targets, regressors).
  std::function<pleat::Body(const Eigen::VectorXd&)> reshape;
};

// A motion is immutable once made; its poses are also kept as the floats
// pleat_poses holds (x y z w per joint, root xyz), so instances evaluate it
// without a copy (pleat_instance_evaluate_motion).
struct pleat_motion {
  pleat_motion(pleat::Motion m, double scale);
  pleat::Motion motion;
  double unit_scale = 1.0;  // metres per file unit that loading applied
  std::vector<float> rotations, root_positions;
};

struct pleat_model {
  std::shared_ptr<const pleat::runtime::Model> model;
};

struct pleat_instance {
  pleat::runtime::Instance instance;
  std::vector<std::string> body_joints;  // the bound body's joint names, in its order
};
