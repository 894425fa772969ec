#include "sequence_inputs.h"

#include <cmath>
#include <filesystem>

#include "body/body_source.h"
#include "body/bvh.h"
#include "capi/pleat.h"
#include "core/error.h"
#include "core/nearest_points.h"
#include "core/topology.h"
#include "io/obj_reader.h"

namespace pleat::datagen {

namespace {

// A .mhclo / .proxy binding and its OBJ's faces (in the order of its "v" lines).
std::pair<ClothesBinding, Triangles> load_clothes(const std::string& path) {
  ClothesBinding binding = read_mhclo(path);
  const std::string obj = (std::filesystem::path(path).parent_path() / binding.obj_file).string();
  const TriMesh mesh = read_obj_file_order(obj);
  if (mesh.vertex_count() != static_cast<int32_t>(binding.vertices.size()))
    fail(PLEAT_ERROR_FORMAT, path + ": binds " + std::to_string(binding.vertices.size()) + " vertices, '" +
                                 obj + "' has " + std::to_string(mesh.vertex_count()));
  if (mesh.triangles.rows() == 0) fail(PLEAT_ERROR_FORMAT, obj + ": the mesh has no faces");
  return {std::move(binding), mesh.triangles};
}

// `rest` skinned to the body with nearest-vertex weights, every frame of `motion`.
std::vector<float> skinned_frames(const Body& body, const Points3d& rest, const Motion& motion) {
  const SkinWeights weights = nearest_vertex_weights(body, rest);
  std::vector<double> skinned(static_cast<size_t>(motion.frame_count * rest.rows() * 3));
  SkinningWorkspace workspace;
  skin_frames(rest, weights, motion, 0, motion.frame_count, &workspace, skinned.data(), skinned.size());
  return {skinned.begin(), skinned.end()};
}

}  // namespace

Assets load_assets(const Config& config) {
  Assets a;
  a.model = MakeHumanModel::load(config.body,
                                 config.rig == "default" ? MakeHumanRig::default_rig : MakeHumanRig::cmu_mb);
  const Body standard = a.model->body(makehuman_default_beta());
  for (const ShapeSpec& s : config.shapes) {
    Eigen::VectorXd beta;
    try {
      beta = shape_values(standard, s.values);
    } catch (const Error& e) {
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           "datagen config '" + config.path + "': shape '" + s.name + "': " + e.what());
    }
    a.bodies.push_back(a.model->body(beta));
    a.shaped.push_back(a.model->shaped_vertices(beta));
  }
  for (const GarmentSpec& g : config.garments) {
    auto [binding, triangles] = load_clothes(g.mhclo);
    a.bindings.push_back(std::move(binding));
    a.garment_triangles.push_back(std::move(triangles));
  }
  if (!config.collider.empty()) std::tie(a.collider, a.collider_triangles) = load_clothes(config.collider);
  for (const MotionSpec& m : config.motions) {
    Motion source = read_bvh(m.source).motion;
    if (m.skip_frames >= source.frame_count)
      fail(PLEAT_ERROR_INVALID_ARGUMENT, "datagen config '" + config.path + "': motion '" + m.name +
                                             "' skips " + std::to_string(m.skip_frames) + " of its " +
                                             std::to_string(source.frame_count) + " frames");
    const int64_t left = source.frame_count - m.skip_frames;
    if (m.take_frames > left)
      fail(PLEAT_ERROR_INVALID_ARGUMENT, "datagen config '" + config.path + "': motion '" + m.name +
                                             "' takes " + std::to_string(m.take_frames) + " frames after " +
                                             std::to_string(m.skip_frames) + " of its " +
                                             std::to_string(source.frame_count) + " (take_frames)");
    source = cut_motion(source, m.skip_frames, m.take_frames != 0 ? m.take_frames : left);
    source.frame_rate *= m.speed;  // the same poses, reached sooner (or later)
    a.motions.push_back(hold_motion(resample_motion(source, config.frame_rate), m.hold_frames));
    a.maps.push_back(m.map.empty() ? JointMap{} : read_joint_map(m.map));
  }
  return a;
}

Eigen::RowVector3d start_velocity(const Motion& clip) {
  const int64_t k = std::min<int64_t>(4, clip.frame_count - 1);  // a few frames: mocap jitters
  if (k == 0) return Eigen::RowVector3d::Zero();
  return (clip.root_translation.row(k) - clip.root_translation.row(0)) * (clip.frame_rate / double(k));
}

Motion with_lead_in(const Motion& clip, int64_t rest_frames, int64_t blend_frames) {
  const int32_t joints = clip.skeleton.joint_count();
  Motion out = clip;
  const int64_t lead = rest_frames + blend_frames;
  out.frame_count = clip.frame_count + lead;
  out.rotations.assign(static_cast<size_t>(out.frame_count * joints), Eigen::Quaterniond::Identity());
  out.root_translation.resize(out.frame_count, 3);
  const Eigen::RowVector3d first = clip.root_translation.row(0), v = start_velocity(clip);
  const double duration = double(blend_frames) / clip.frame_rate;
  for (int64_t f = 0; f < lead; ++f) {
    const double u = f < rest_frames ? 0.0 : double(f - rest_frames) / double(blend_frames);
    const double t = u * u * (3.0 - 2.0 * u);  // smoothstep: starts and ends at rest
    for (int32_t j = 0; j < joints; ++j)
      out.rotations[static_cast<size_t>(f * joints + j)] =
          Eigen::Quaterniond::Identity().slerp(t, clip.frame(0)[j]);
    // Velocity eases in as smoothstep(u): position = first - v T (1/2 - u^3 + u^4 / 2).
    out.root_translation.row(f) = first - v * duration * (0.5 - u * u * u + 0.5 * u * u * u * u);
  }
  std::copy(clip.rotations.begin(), clip.rotations.end(), out.rotations.begin() + lead * joints);
  out.root_translation.bottomRows(clip.frame_count) = clip.root_translation;
  return out;
}

std::vector<int32_t> pinned_vertices(const Body& body, const TriMesh& garment, double distance, double band) {
  std::vector<int32_t> pinned;
  if (distance <= 0) return pinned;
  const Points3d& x = garment.vertices;
  std::vector<int32_t> label;
  const int32_t components =
      connected_components(edge_graph(unique_edges(garment.triangles), garment.vertex_count()), &label);
  std::vector<double> top(static_cast<size_t>(components), -1e300);
  std::vector<int32_t> size(static_cast<size_t>(components), 0);
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    top[static_cast<size_t>(label[v])] = std::max(top[static_cast<size_t>(label[v])], x(v, 1));
    ++size[static_cast<size_t>(label[v])];
  }
  const std::vector<int32_t> nearest = nearest_points(body.rest.vertices, x);
  std::vector<uint8_t> in_band(static_cast<size_t>(x.rows())), close(static_cast<size_t>(x.rows()));
  std::vector<int32_t> close_in_band(static_cast<size_t>(components), 0);
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    const auto c = static_cast<size_t>(label[v]);
    in_band[v] = x(v, 1) > top[c] - band;
    close[v] = (x.row(v) - body.rest.vertices.row(nearest[static_cast<size_t>(v)])).norm() < distance;
    close_in_band[c] += in_band[v] && close[v];
  }
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    const auto c = static_cast<size_t>(label[v]);
    const bool pin = size[c] <= kRigidPieceVertices || (in_band[v] && (close[v] || close_in_band[c] == 0));
    if (pin) pinned.push_back(static_cast<int32_t>(v));
  }
  return pinned;
}

void stretch_hem(Points3d* vertices, double below, double factor) {
  auto y = vertices->col(1);
  const double lowest = y.minCoeff();
  const double cut = lowest + below * (y.maxCoeff() - lowest);
  for (Eigen::Index v = 0; v < y.size(); ++v)
    if (y(v) < cut) y(v) = cut - factor * (cut - y(v));
}

SequenceInputs prepare_sequence(const Config& config, const Assets& assets, const Job& job) {
  SequenceInputs in;
  const Body& body = assets.bodies[job.shape];
  in.body = &body;
  in.garment_rest.vertices = fit_clothes(assets.bindings[job.garment], assets.shaped[job.shape]);
  in.garment_rest.triangles = assets.garment_triangles[job.garment];
  const GarmentSpec& g = config.garments[job.garment];
  if (g.stretched()) stretch_hem(&in.garment_rest.vertices, g.stretch_below, g.stretch_factor);

  RetargetOptions options;
  const JointMap& map = assets.maps[job.segment.motion];
  if (!map.entries.empty()) options.map = &map;
  Motion clip = retarget_motion(assets.motions[job.segment.motion], body.skeleton, options);
  clip = cut_motion(clip, job.segment.first, job.segment.count);
  if (job.segment.mirrored) clip = mirror_motion(clip);
  // Start where the body stands at rest: shifted so the lead-in's first root
  // position is the rest root's. Lifting the
  // body from its rest height (MakeHuman's origin is near the crotch, clips
  // stand on the ground) or dragging it from where the clip was recorded would
  // tear the cloth along. The network never sees absolute positions
  // (runtime/frame_features.h), and there is no floor to stand on.
  in.motion = with_lead_in(clip, config.rest_frames, config.blend_frames);
  // The turn eases in with the blend, so the cloth is not jolted into a spin.
  const double turn = config.motions[job.segment.motion].turn;
  if (turn != 0.0) in.motion = turn_motion(in.motion, turn, config.rest_frames, config.blend_frames);
  in.root_offset = in.motion.root_translation.row(0) - body.skeleton.rest_translation.row(0);
  in.motion.root_translation.rowwise() -= in.root_offset.transpose();
  in.lead_in = config.rest_frames + config.blend_frames;

  const Points3d posed = pose_body_frames(body, in.motion, 0, in.motion.frame_count);
  in.body_frames.assign(posed.data(), posed.data() + posed.size());
  in.garment_skinned = skinned_frames(body, in.garment_rest.vertices, in.motion);
  if (!assets.collider.vertices.empty()) {
    in.collider_rest.vertices = fit_clothes(assets.collider, assets.shaped[job.shape]);
    in.collider_rest.triangles = assets.collider_triangles;
    in.collider_frames = skinned_frames(body, in.collider_rest.vertices, in.motion);
  }
  in.pinned = pinned_vertices(body, in.garment_rest, g.pin_distance, g.pin_band);
  return in;
}

}  // namespace pleat::datagen
