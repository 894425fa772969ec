#include "body/body_source.h"

#include <cmath>
#include <filesystem>
#include <memory>

#include "body/makehuman.h"
#include "body/rig_import.h"
#include "body/smpl_npz.h"
#include "capi/pleat.h"
#include "core/error.h"

namespace pleat {
namespace {

uint32_t resolve_kind(const std::string& path, uint32_t kind) {
  if (kind != PLEAT_BODY_AUTO) return kind;
  if (std::filesystem::is_directory(path)) return PLEAT_BODY_MAKEHUMAN;
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".npz" || ext == ".NPZ" ? PLEAT_BODY_SMPL_NPZ : PLEAT_BODY_RIGGED_MESH;
}

}  // namespace

BodySource load_body_source(const std::string& path, uint32_t kind, uint32_t rig) {
  switch (resolve_kind(path, kind)) {
    case PLEAT_BODY_MAKEHUMAN: {
      if (rig > PLEAT_RIG_MAKEHUMAN_DEFAULT)
        fail(PLEAT_ERROR_INVALID_ARGUMENT, "body rig has unknown value " + std::to_string(rig));
      auto model = MakeHumanModel::load(
          path, rig == PLEAT_RIG_CMU_MB ? MakeHumanRig::cmu_mb : MakeHumanRig::default_rig);
      return {model->body(makehuman_default_beta()),
              [model](const Eigen::VectorXd& beta) { return model->body(beta); }};
    }
    case PLEAT_BODY_SMPL_NPZ: {
      auto model = std::make_shared<const SmplModel>(load_smpl_npz(path));
      return {smpl_body(*model, Eigen::VectorXd::Zero(model->shape_count())),
              [model](const Eigen::VectorXd& beta) { return smpl_body(*model, beta); }};
    }
    case PLEAT_BODY_RIGGED_MESH: return {import_rig(path).body, {}};
    default: fail(PLEAT_ERROR_INVALID_ARGUMENT, "body kind has unknown value " + std::to_string(kind));
  }
}

Eigen::VectorXd shape_values(const Body& body, const std::vector<std::pair<std::string, double>>& named) {
  Eigen::VectorXd values = body.beta();
  for (const auto& [name, value] : named) {
    size_t i = 0;
    while (i < body.shape.size() && body.shape[i].name != name) ++i;
    if (i == body.shape.size())
      fail(PLEAT_ERROR_INVALID_ARGUMENT, "body '" + body.source + "' has no shape entry '" + name + "'");
    const ShapeParameter& p = body.shape[i];
    if (!(std::isfinite(value) && value >= p.min && value <= p.max))
      fail(PLEAT_ERROR_INVALID_ARGUMENT, "shape entry '" + name + "' = " + std::to_string(value) +
                                             " is outside [" + std::to_string(p.min) + ", " +
                                             std::to_string(p.max) + "]");
    values[static_cast<Eigen::Index>(i)] = value;
  }
  return values;
}

}  // namespace pleat
