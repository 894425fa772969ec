// C entry points for bodies: the MakeHuman model, SMPL-layout files and
// rigged characters; reshaping and posing.
#include <filesystem>

#include "body/makehuman.h"
#include "body/smpl_npz.h"
#include "capi/firewall.h"
#include "capi/frames.h"
#include "capi/handles.h"
#include "io/obj_writer.h"
#include "io/rig_import.h"

using namespace pleat;
using namespace pleat::capi;

namespace {

uint32_t resolve_kind(const std::string& path, uint32_t kind) {
  if (kind != PLEAT_BODY_AUTO) return kind;
  if (std::filesystem::is_directory(path)) return PLEAT_BODY_MAKEHUMAN;
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".npz" || ext == ".NPZ" ? PLEAT_BODY_SMPL_NPZ : PLEAT_BODY_RIGGED_MESH;
}

pleat_body* load_body(const std::string& path, const pleat_body_load_options& o) {
  switch (resolve_kind(path, o.kind)) {
    case PLEAT_BODY_MAKEHUMAN: {
      require(o.rig <= PLEAT_RIG_MAKEHUMAN_DEFAULT,
              "'pleat_body_load_options.rig' has unknown value " + std::to_string(o.rig));
      auto model = MakeHumanModel::load(
          path, o.rig == PLEAT_RIG_CMU_MB ? MakeHumanRig::cmu_mb : MakeHumanRig::default_rig);
      return new pleat_body{model->body(makehuman_default_beta()),
                            [model](const Eigen::VectorXd& beta) { return model->body(beta); }};
    }
    case PLEAT_BODY_SMPL_NPZ: {
      auto model = std::make_shared<const SmplModel>(load_smpl_npz(path));
      return new pleat_body{smpl_body(*model, Eigen::VectorXd::Zero(model->shape_count())),
                            [model](const Eigen::VectorXd& beta) { return smpl_body(*model, beta); }};
    }
    case PLEAT_BODY_RIGGED_MESH: return new pleat_body{import_rig(path).body, {}};
    default:
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           "'pleat_body_load_options.kind' has unknown value " + std::to_string(o.kind));
  }
}

template <typename T>
void check_capacity(const T* out, size_t capacity, size_t needed, const char* name) {
  if (out && capacity < needed)
    fail(PLEAT_ERROR_BUFFER_TOO_SMALL, std::string(name) + " capacity " + std::to_string(capacity) +
                                           " is below the " + std::to_string(needed) + " needed");
}

}  // namespace

extern "C" {

pleat_status pleat_body_load(const char* path, const pleat_body_load_options* options,
                             pleat_body** out_body) {
  return guarded(__func__, [&] {
    require_not_null(path, "path");
    require_not_null(out_body, "out_body");
    *out_body = load_body(path, read_options(options, "pleat_body_load_options"));
  });
}

void pleat_body_destroy(pleat_body* body) {
  delete body;
}

pleat_status pleat_body_get_info(const pleat_body* body, pleat_body_info* out_info) {
  return guarded(__func__, [&] {
    require_not_null(body, "body");
    const Body& b = body->body;
    pleat_body_info info{};
    info.struct_size = sizeof info;
    info.vertex_count = static_cast<uint32_t>(b.vertex_count());
    info.triangle_count = static_cast<uint32_t>(b.rest.triangle_count());
    info.joint_count = static_cast<uint32_t>(b.joint_count());
    info.shape_count = static_cast<uint32_t>(b.shape.size());
    info.max_influences = static_cast<uint32_t>(b.weights.max_influences());
    write_result(info, out_info, "out_info");
  });
}

const char* pleat_body_joint_name(const pleat_body* body, uint32_t index) {
  if (!body || index >= body->body.skeleton.names.size()) return nullptr;
  return body->body.skeleton.names[index].c_str();
}

const char* pleat_body_shape_name(const pleat_body* body, uint32_t index) {
  if (!body || index >= body->body.shape.size()) return nullptr;
  return body->body.shape[index].name.c_str();
}

pleat_status pleat_body_get_shape(const pleat_body* body, double* values, size_t capacity) {
  return guarded(__func__, [&] {
    require_not_null(body, "body");
    require_not_null(values, "values");
    const Eigen::VectorXd beta = body->body.beta();
    check_capacity(values, capacity, static_cast<size_t>(beta.size()), "values");
    Eigen::Map<Eigen::VectorXd>(values, beta.size()) = beta;
  });
}

pleat_status pleat_body_set_shape(pleat_body* body, const double* values, size_t count) {
  return guarded(__func__, [&] {
    require_not_null(body, "body");
    require(static_cast<bool>(body->reshape), "body '" + body->body.source + "' has a fixed shape");
    require(count == body->body.shape.size(), "count " + std::to_string(count) + " differs from the body's " +
                                                  std::to_string(body->body.shape.size()) + " shape entries");
    require_not_null(values, "values");
    for (size_t i = 0; i < count; ++i) {
      const ShapeParameter& p = body->body.shape[i];
      require(std::isfinite(values[i]) && values[i] >= p.min && values[i] <= p.max,
              "shape entry " + std::to_string(i) + " '" + p.name + "' = " + std::to_string(values[i]) +
                  " is outside [" + std::to_string(p.min) + ", " + std::to_string(p.max) + "]");
    }
    body->body = body->reshape(Eigen::Map<const Eigen::VectorXd>(values, static_cast<Eigen::Index>(count)));
  });
}

pleat_status pleat_body_get_rest(const pleat_body* body, float* positions, size_t positions_capacity,
                                 uint32_t* triangles, size_t triangles_capacity, float* joints,
                                 size_t joints_capacity) {
  return guarded(__func__, [&] {
    require_not_null(body, "body");
    const Body& b = body->body;
    const Points3d j = rest_joint_positions(b.skeleton);
    check_capacity(positions, positions_capacity, static_cast<size_t>(b.rest.vertices.size()), "positions");
    check_capacity(triangles, triangles_capacity, static_cast<size_t>(b.rest.triangles.size()), "triangles");
    check_capacity(joints, joints_capacity, static_cast<size_t>(j.size()), "joints");
    if (positions) Eigen::Map<Points3f>(positions, b.rest.vertices.rows(), 3) = b.rest.vertices.cast<float>();
    if (triangles)
      for (Eigen::Index i = 0; i < b.rest.triangles.size(); ++i)
        triangles[i] = static_cast<uint32_t>(b.rest.triangles.data()[i]);
    if (joints) Eigen::Map<Points3f>(joints, j.rows(), 3) = j.cast<float>();
  });
}

pleat_status pleat_body_pose_motion(const pleat_body* body, const pleat_motion* motion, size_t first_frame,
                                    size_t frame_count, pleat_frames out) {
  return guarded(__func__, [&] {
    require_not_null(body, "body");
    require_not_null(motion, "motion");
    require_not_null(out.data, "out.data");
    const auto n = static_cast<size_t>(body->body.vertex_count());
    const size_t stride = resolved_stride(out.frame_stride, n, "out");
    const Points3d posed = pose_body_frames(body->body, motion->motion, static_cast<int64_t>(first_frame),
                                            static_cast<int64_t>(frame_count));
    for (size_t f = 0; f < frame_count; ++f)
      Eigen::Map<Points3f>(out.data + f * stride, static_cast<Eigen::Index>(n), 3) =
          posed.middleRows(static_cast<Eigen::Index>(f * n), static_cast<Eigen::Index>(n)).cast<float>();
  });
}

pleat_status pleat_mesh_write_obj(const char* path, const float* positions, size_t vertex_count,
                                  const uint32_t* triangles, size_t triangle_count) {
  return guarded(__func__, [&] {
    require_not_null(path, "path");
    require_not_null(positions, "positions");
    require_not_null(triangles, "triangles");
    Triangles t(static_cast<Eigen::Index>(triangle_count), 3);
    for (size_t i = 0; i < triangle_count * 3; ++i) t.data()[i] = static_cast<int32_t>(triangles[i]);
    write_obj(path, positions, vertex_count, t);
  });
}

}  // extern "C"
