#pragma once
// Band settings, mirroring pleat_prepare_options in the C API.
#include <cstdint>

#include "capi/pleat.h"

namespace pleat {

enum class SolverKind : uint32_t {
  automatic = PLEAT_SOLVER_AUTO,
  dense = PLEAT_SOLVER_DENSE,
  slicing = PLEAT_SOLVER_SLICING,
  hybrid = PLEAT_SOLVER_HYBRID,
};

enum class ProjectionForm : uint32_t {
  random_walk = PLEAT_PROJECTION_RANDOM_WALK,
  symmetric = PLEAT_PROJECTION_SYMMETRIC,
};

struct BandOptions {
  double low_fraction = 1.0 / 30.0;  // low/mid cut requested at ceil(N * low_fraction)
  double mid_fraction = 0.2;         // mid/high cut requested at ceil(N * mid_fraction)
  SolverKind solver = SolverKind::automatic;
  ProjectionForm projection = ProjectionForm::random_walk;
};

}  // namespace pleat
