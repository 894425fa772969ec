#include "body/makehuman.h"

#include <filesystem>
#include <map>
#include <mutex>
#include <set>

#include "body/makehuman_rig.h"
#include "body/makehuman_targets.h"
#include "core/error.h"
#include "io/obj_reader.h"

namespace pleat {
namespace {

constexpr double kDecimetre = 0.1;

// Everything of a body directory that does not depend on the rig; both rigs
// of a directory share it.
struct MakeHumanData {
  explicit MakeHumanData(const std::string& directory)
      : dir(directory), targets(directory, kMakeHumanVertexCount) {
    const std::string path = dir + "/base.obj";
    ObjGroups obj_groups;
    const TriMesh mesh = read_obj_file_order(path, &obj_groups);
    if (mesh.vertex_count() != kMakeHumanVertexCount)
      fail(PLEAT_ERROR_FORMAT, path + ": " + std::to_string(mesh.vertex_count()) +
                                   " vertices, the hm08 base mesh has " +
                                   std::to_string(kMakeHumanVertexCount));
    for (int32_t g : obj_groups.of_triangle)
      if (g < 0) fail(PLEAT_ERROR_FORMAT, path + ": a face comes before any 'g' line");
    base = mesh.vertices;
    triangles = mesh.triangles;
    groups = std::move(obj_groups.names);
    triangle_group = std::move(obj_groups.of_triangle);
  }

  // The triangles whose group passes `keep`.
  template <typename Keep>
  Triangles triangles_where(Keep keep) const {
    std::vector<int32_t> tri;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
      if (keep(groups[static_cast<size_t>(triangle_group[static_cast<size_t>(t)])]))
        tri.insert(tri.end(), {triangles(t, 0), triangles(t, 1), triangles(t, 2)});
    return Eigen::Map<Triangles>(tri.data(), static_cast<Eigen::Index>(tri.size() / 3), 3);
  }

  std::string dir;
  Points3d base;        // decimetres, all vertices
  Triangles triangles;  // quads split, all groups
  std::vector<std::string> groups;
  std::vector<int32_t> triangle_group;
  MakeHumanTargets targets;
};

// Loaded data and models, shared while someone holds them: a long-running
// host that drops its last body frees them.
std::mutex g_cache_mutex;
std::map<std::string, std::weak_ptr<MakeHumanData>> g_data;
std::map<std::pair<std::string, int>, std::weak_ptr<const MakeHumanModel>> g_models;

std::string canonical_dir(const std::string& dir) {
  std::error_code ec;
  auto p = std::filesystem::weakly_canonical(dir, ec);
  return ec ? dir : p.string();
}

std::shared_ptr<MakeHumanData> shared_data(const std::string& dir) {
  // Called with g_cache_mutex held.
  if (auto d = g_data[dir].lock()) return d;
  auto d = std::make_shared<MakeHumanData>(dir);
  g_data[dir] = d;
  return d;
}

const char* rig_name(MakeHumanRig rig) {
  return rig == MakeHumanRig::cmu_mb ? "cmu_mb" : "default";
}

}  // namespace

struct MakeHumanModel::Impl {
  std::shared_ptr<MakeHumanData> data;
  std::vector<std::vector<int32_t>> joint_vertices;  // per skeleton joint: its head's vertex group
  Triangles body_triangles;
  Triangles body_and_helper_triangles;
};

MakeHumanModel::MakeHumanModel() : impl_(std::make_unique<Impl>()) {}
MakeHumanModel::~MakeHumanModel() = default;

std::shared_ptr<const MakeHumanModel> MakeHumanModel::load(const std::string& body_dir, MakeHumanRig rig) {
  const std::string dir = canonical_dir(body_dir);
  std::lock_guard<std::mutex> lock(g_cache_mutex);
  const auto key = std::make_pair(dir, static_cast<int>(rig));
  if (auto loaded = g_models[key].lock()) return loaded;
  if (!std::filesystem::is_directory(dir)) fail(PLEAT_ERROR_IO, body_dir + ": no such body data directory");

  auto model = std::shared_ptr<MakeHumanModel>(new MakeHumanModel());
  model->rig_ = rig;
  model->dir_ = dir;
  Impl& impl = *model->impl_;
  impl.data = shared_data(dir);
  const MakeHumanData& d = *impl.data;

  const std::string rig_path =
      dir + (rig == MakeHumanRig::cmu_mb ? "/rigs/cmu_mb.mhskel" : "/rigs/default.mhskel");
  const std::string weights_path =
      dir + (rig == MakeHumanRig::cmu_mb ? "/rigs/mpfb2_weights.cmu_mb.json" : "/rigs/default_weights.mhw");
  read_makehuman_rig(rig_path, kMakeHumanVertexCount, &model->skeleton_, &impl.joint_vertices);
  model->all_weights_ =
      read_makehuman_weights(weights_path, model->skeleton_, kMakeHumanVertexCount, &model->unweighted_);

  impl.body_triangles = d.triangles_where([](const std::string& g) { return g == "body"; });
  if (impl.body_triangles.rows() == 0) fail(PLEAT_ERROR_FORMAT, dir + "/base.obj: no 'body' group faces");
  if (impl.body_triangles.maxCoeff() >= kMakeHumanBodyVertexCount)
    fail(PLEAT_ERROR_FORMAT,
         dir + "/base.obj: a 'body' face uses vertex " + std::to_string(impl.body_triangles.maxCoeff()) +
             ", outside the body range 0.." + std::to_string(kMakeHumanBodyVertexCount - 1));
  impl.body_and_helper_triangles =
      d.triangles_where([](const std::string& g) { return g.rfind("joint-", 0) != 0; });

  // Rest translations of the default shape.
  const Points3d joints = model->joint_positions(model->shaped_vertices(makehuman_default_beta()));
  for (int32_t j = 0; j < model->skeleton_.joint_count(); ++j)
    model->skeleton_.rest_translation.row(j) =
        j == 0 ? joints.row(0) : Eigen::RowVector3d(joints.row(j) - joints.row(model->skeleton_.parents[j]));
  validate_skeleton(model->skeleton_, rig_path);
  g_models[key] = model;
  return model;
}

std::vector<std::pair<std::string, double>> MakeHumanModel::target_weights(
    const Eigen::VectorXd& beta) const {
  return impl_->data->targets.weights(beta);
}

Points3d MakeHumanModel::shaped_vertices(const Eigen::VectorXd& beta) const {
  Points3d x = impl_->data->base;
  impl_->data->targets.add_to(beta, &x);
  return x * kDecimetre;
}

Points3d MakeHumanModel::joint_positions(const Points3d& shaped) const {
  if (shaped.rows() != kMakeHumanVertexCount)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "makehuman: joint_positions needs all " +
                                           std::to_string(kMakeHumanVertexCount) + " vertices, got " +
                                           std::to_string(shaped.rows()));
  const auto n = static_cast<Eigen::Index>(impl_->joint_vertices.size());
  Points3d j = Points3d::Zero(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& vs = impl_->joint_vertices[static_cast<size_t>(i)];
    for (int32_t v : vs) j.row(i) += shaped.row(v);
    j.row(i) /= static_cast<double>(vs.size());
  }
  return j;
}

Body MakeHumanModel::body(const Eigen::VectorXd& beta) const {
  const Points3d all = shaped_vertices(beta);
  const Points3d joints = joint_positions(all);
  Body b;
  b.source = std::string("makehuman:") + rig_name(rig_);
  b.skeleton = skeleton_;
  for (int32_t j = 0; j < skeleton_.joint_count(); ++j)
    b.skeleton.rest_translation.row(j) =
        j == 0 ? joints.row(0) : Eigen::RowVector3d(joints.row(j) - joints.row(skeleton_.parents[j]));
  b.rest.vertices = all.topRows(kMakeHumanBodyVertexCount);
  b.rest.triangles = impl_->body_triangles;
  b.weights.joint_count = all_weights_.joint_count;
  b.weights.offsets.assign(all_weights_.offsets.begin(),
                           all_weights_.offsets.begin() + kMakeHumanBodyVertexCount + 1);
  const auto nnz = static_cast<size_t>(b.weights.offsets.back());
  b.weights.joints.assign(all_weights_.joints.begin(),
                          all_weights_.joints.begin() + static_cast<std::ptrdiff_t>(nnz));
  b.weights.weights.assign(all_weights_.weights.begin(),
                           all_weights_.weights.begin() + static_cast<std::ptrdiff_t>(nnz));
  b.shape = makehuman_shape_parameters();
  for (int i = 0; i < kMakeHumanBetaCount; ++i) b.shape[static_cast<size_t>(i)].value = beta[i];
  return b;
}

Body MakeHumanModel::body_with_helpers(const Eigen::VectorXd& beta) const {
  Body b = body(beta);
  b.source += "+helpers";
  b.rest.vertices = shaped_vertices(beta);
  b.rest.triangles = impl_->body_and_helper_triangles;
  b.weights = all_weights_;
  return b;
}

std::vector<std::string> MakeHumanModel::group_names() const {
  return impl_->data->groups;
}

std::vector<int32_t> MakeHumanModel::group_vertices(const std::string& group) const {
  const Triangles tri = group_triangles(group);
  const std::set<int32_t> vs(tri.data(), tri.data() + tri.size());
  return {vs.begin(), vs.end()};
}

Triangles MakeHumanModel::group_triangles(const std::string& group) const {
  Triangles tri = impl_->data->triangles_where([&](const std::string& g) { return g == group; });
  if (tri.rows() == 0) fail(PLEAT_ERROR_INVALID_ARGUMENT, "makehuman: base.obj has no group '" + group + "'");
  return tri;
}

}  // namespace pleat
