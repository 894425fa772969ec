#pragma once
// What the opaque C handles are.
#include <functional>
#include <string>

#include "body/body.h"
#include "body/skeleton.h"
#include "core/garment.h"

struct pleat_garment {
  pleat::Garment garment;
};

struct pleat_body {
  pleat::Body body;
  // Rebuilds the body for a shape vector; empty for fixed-shape bodies
  // (rigged meshes). Shares the immutable model data (targets, regressors).
  std::function<pleat::Body(const Eigen::VectorXd&)> reshape;
};

struct pleat_motion {
  pleat::Motion motion;
  double unit_scale = 1.0;  // metres per file unit that loading applied
};
