// C entry points for bodies: the MakeHuman model, SMPL-layout files and
// rigged characters; reshaping and posing.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "body/body_source.h"
#include "body/rig_import.h"
#include "capi/firewall.h"
#include "capi/frames.h"
#include "capi/handles.h"
#include "io/obj_writer.h"

using namespace pleat;
using namespace pleat::capi;

namespace {

pleat_body* load_body(const std::string& path, const pleat_body_load_options& o) {
  PLEAT_REQUIRE(o.kind <= PLEAT_BODY_RIGGED_MESH,
                "'pleat_body_load_options.kind' has unknown value " + std::to_string(o.kind));
  PLEAT_REQUIRE(o.rig <= PLEAT_RIG_MAKEHUMAN_DEFAULT,
                "'pleat_body_load_options.rig' has unknown value " + std::to_string(o.rig));
  BodySource source = load_body_source(path, o.kind, o.rig);
  return new pleat_body{std::move(source.body), std::move(source.reshape)};
}

template <typename T>
void check_capacity(const T* out, size_t capacity, size_t needed, const char* name) {
  if (out && capacity < needed)
    fail(PLEAT_ERROR_BUFFER_TOO_SMALL, std::string(name) + " capacity " + std::to_string(capacity) +
                                           " is below the " + std::to_string(needed) + " needed");
}

Body body_from_desc(const pleat_body_desc& d) {
  PLEAT_REQUIRE(d.joint_count > 0, "'pleat_body_desc.joint_count' is 0");
  for (const void* field : {static_cast<const void*>(d.joint_names), static_cast<const void*>(d.parents),
                            static_cast<const void*>(d.joint_positions),
                            static_cast<const void*>(d.positions), static_cast<const void*>(d.triangles),
                            static_cast<const void*>(d.weight_joints), static_cast<const void*>(d.weights)})
    PLEAT_REQUIRE(field != nullptr, "a pointer field of pleat_body_desc is NULL");
  PLEAT_REQUIRE(d.influences > 0, "'pleat_body_desc.influences' is 0");
  PLEAT_REQUIRE(d.vertex_count < (size_t{1} << 30) && d.triangle_count < (size_t{1} << 30),
                "'pleat_body_desc' vertex_count or triangle_count exceeds 2^30");
  Body b;
  b.source = "caller arrays";
  const auto joints = static_cast<Eigen::Index>(d.joint_count);
  Skeleton& s = b.skeleton;
  const Points3d global = Eigen::Map<const Points3f>(d.joint_positions, joints, 3).cast<double>();
  s.rest_translation.resize(joints, 3);
  for (Eigen::Index j = 0; j < joints; ++j) {
    PLEAT_REQUIRE(d.joint_names[j] != nullptr,
                  "'pleat_body_desc.joint_names[" + std::to_string(j) + "]' is NULL");
    s.names.emplace_back(d.joint_names[j]);
    s.parents.push_back(d.parents[j]);
    s.rest_rotation.push_back(Eigen::Quaterniond::Identity());
    const bool valid_parent = d.parents[j] >= 0 && d.parents[j] < j;
    s.rest_translation.row(j) = valid_parent ? Eigen::RowVector3d(global.row(j) - global.row(d.parents[j]))
                                             : Eigen::RowVector3d(global.row(j));
  }
  validate_skeleton(s, b.source);
  const auto n = static_cast<Eigen::Index>(d.vertex_count);
  b.rest.vertices = Eigen::Map<const Points3f>(d.positions, n, 3).cast<double>();
  b.rest.triangles =
      caller_triangles(d.triangles, d.triangle_count, d.vertex_count, "pleat_body_desc.triangles");
  SkinWeights& w = b.weights;
  w.joint_count = static_cast<int32_t>(d.joint_count);
  for (size_t v = 0; v < d.vertex_count; ++v) {
    std::vector<std::pair<int32_t, double>> pairs;
    for (size_t k = 0; k < d.influences; ++k) {
      const size_t at = v * d.influences + k;
      PLEAT_REQUIRE(d.weight_joints[at] < d.joint_count,
                    "'pleat_body_desc.weight_joints[" + std::to_string(at) +
                        "]' = " + std::to_string(d.weight_joints[at]) + " is not below joint_count");
      if (d.weights[at] != 0.0f) pairs.emplace_back(static_cast<int32_t>(d.weight_joints[at]), d.weights[at]);
    }
    std::sort(pairs.begin(), pairs.end());
    for (const auto& [joint, weight] : pairs) {
      PLEAT_REQUIRE(w.joints.size() == static_cast<size_t>(w.offsets.back()) || w.joints.back() != joint,
                    "vertex " + std::to_string(v) + " names joint " + std::to_string(joint) + " twice");
      w.joints.push_back(joint);
      w.weights.push_back(weight);
    }
    w.offsets.push_back(static_cast<int32_t>(w.joints.size()));
  }
  validate_body(b, b.source);
  return b;
}

}  // namespace

extern "C" {

pleat_status pleat_body_create(const pleat_body_desc* desc, pleat_body** out_body) {
  return guarded(__func__, [&] {
    require_not_null(desc, "desc");
    require_not_null(out_body, "out_body");
    *out_body = new pleat_body{body_from_desc(read_options(desc, "pleat_body_desc")), {}};
  });
}

pleat_status pleat_body_pose(const pleat_body* body, const float* rotations, const float* root_positions,
                             size_t frame_count, pleat_frames out) {
  return guarded(__func__, [&] {
    require_not_null(body, "body");
    require_not_null(rotations, "rotations");
    require_not_null(root_positions, "root_positions");
    require_not_null(out.data, "out.data");
    const Body& b = body->body;
    const auto joints = static_cast<size_t>(b.joint_count()), n = static_cast<size_t>(b.vertex_count());
    const size_t stride = resolved_stride(out.frame_stride, n, "out");
    // Check every frame before writing any, so a failure leaves `out` untouched.
    Quaternions pose(frame_count * joints);
    for (size_t f = 0; f < frame_count; ++f) {
      for (size_t j = 0; j < joints; ++j) {
        const float* q = rotations + (f * joints + j) * 4;
        const Eigen::Quaterniond r(q[3], q[0], q[1], q[2]);
        PLEAT_REQUIRE(r.coeffs().allFinite() && std::abs(r.norm() - 1.0) < 1e-3,
                      "rotation of frame " + std::to_string(f) + " joint " + std::to_string(j) + " '" +
                          b.skeleton.names[j] + "' is not a finite unit quaternion");
        pose[f * joints + j] = r.normalized();
      }
      for (int c = 0; c < 3; ++c)
        PLEAT_REQUIRE(std::isfinite(root_positions[f * 3 + c]),
                      "root position of frame " + std::to_string(f) + " is not finite");
    }
    BodyWorkspace workspace;
    Points3d posed;
    for (size_t f = 0; f < frame_count; ++f) {
      const Eigen::Vector3d root = Eigen::Map<const Eigen::Vector3f>(root_positions + f * 3).cast<double>();
      pose_body(b, pose.data() + f * joints, root, &posed, &workspace);
      Eigen::Map<Points3f>(out.data + f * stride, static_cast<Eigen::Index>(n), 3) = posed.cast<float>();
    }
  });
}

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
    PLEAT_REQUIRE(static_cast<bool>(body->reshape), "body '" + body->body.source + "' has a fixed shape");
    PLEAT_REQUIRE(count == body->body.shape.size(),
                  "count " + std::to_string(count) + " differs from the body's " +
                      std::to_string(body->body.shape.size()) + " shape entries");
    require_not_null(values, "values");
    for (size_t i = 0; i < count; ++i) {
      const ShapeParameter& p = body->body.shape[i];
      PLEAT_REQUIRE(std::isfinite(values[i]) && values[i] >= p.min && values[i] <= p.max,
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
    write_obj(path, positions, vertex_count,
              caller_triangles(triangles, triangle_count, vertex_count, "triangles"));
  });
}

}  // extern "C"
