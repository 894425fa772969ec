#pragma once
// A body by path, with the shape model behind it: a MakeHuman assets folder
// (the open body model), an SMPL-layout .npz, or any rigged FBX/glTF
// character (fixed shape). Shared by the C API and the trainer's data sets.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "body/body.h"

namespace pleat {

struct BodySource {
  Body body;  // at the model's default shape
  // Rebuilds the body for a shape vector; empty for fixed-shape bodies.
  std::function<Body(const Eigen::VectorXd&)> reshape;
};

// kind: PLEAT_BODY_* (AUTO: a folder is MakeHuman, .npz SMPL layout, else a
// rigged mesh); rig: PLEAT_RIG_* (MakeHuman only). Throws the loaders' errors
// and PLEAT_ERROR_INVALID_ARGUMENT for an unknown kind or rig.
BodySource load_body_source(const std::string& path, uint32_t kind, uint32_t rig);

// The shape vector with the named entries set (the others at their
// defaults). Throws PLEAT_ERROR_INVALID_ARGUMENT naming an unknown entry or a
// value outside its range, or when the body has a fixed shape.
Eigen::VectorXd shape_values(const Body& body, const std::vector<std::pair<std::string, double>>& named);

}  // namespace pleat
