#pragma once
// The MakeHuman open body model (CC0 hm08 base mesh): shape β = the macro
// sliders, blended from the macro targets; joints = mean of the rig's joint
// vertex groups after shaping; skinning with the rig's weights.
//
// Data: a directory laid out like shared/data/body (base.obj, rigs/,
// targets/macrodetails/ with MANIFEST.tsv); see BODY_NOTES.md there and
// docs/bodies.md. base.obj is in decimetres; everything returned is in metres.
//
// β (9 entries, all in [0, 1]):
//   0 gender      0 female .. 1 male                         default 0.5
//   1 age         0 = 1 yr, 0.1875 = 10 yr, 0.5 = 25, 1 = 90  default 0.5
//   2 muscle      0 min .. 1 max                              default 0.5
//   3 weight      0 min .. 1 max                              default 0.5
//   4 height      0 short .. 1 tall                           default 0.5
//   5 proportions 0 uncommon .. 1 ideal                       default 0.5
//   6 african, 7 asian, 8 caucasian: ethnic mix, renormalised to sum 1
//                                                             default 1/3 each
// The model keeps all 19158 base.obj vertices (body, helper shells such as
// helper-tights and helper-skirt used to fit garments, joint cubes) and
// exposes the body group (vertices 0..13379) as the Body's mesh.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "body/body.h"

namespace pleat {

enum class MakeHumanRig {
  cmu_mb,       // 31 bones named like the CMU MotionBuilder BVH skeleton; MPFB2 weights
  default_rig,  // MakeHuman's default 163-bone skeleton; default_weights.mhw
};

constexpr int32_t kMakeHumanVertexCount = 19158;      // all of base.obj
constexpr int32_t kMakeHumanBodyVertexCount = 13380;  // the `body` group: vertices 0..13379
constexpr int kMakeHumanBetaCount = 9;

// The β definition with default values (see above).
std::vector<ShapeParameter> makehuman_shape_parameters();
Eigen::VectorXd makehuman_default_beta();

// Per-category values of the macro sliders (BODY_NOTES.md), by token name
// ("male", "young", "averagemuscle", "maxheight", "caucasian", ...).
// Throws PLEAT_ERROR_INVALID_ARGUMENT naming the parameter for a β of the
// wrong size, a value outside [0, 1] or non-finite, or ethnic values summing to 0.
std::vector<std::pair<std::string, double>> makehuman_category_values(const Eigen::VectorXd& beta);

class MakeHumanModel {
 public:
  // Loads base.obj, the rig and its weights and the target manifest from
  // `body_dir`. Target files are parsed on first use and kept with the
  // model (both rigs of one directory share them). While a caller holds a
  // model, loading the same (directory, rig) again returns it for free; the
  // last holder's release frees it all. Throws PLEAT_ERROR_IO for
  // a missing file and PLEAT_ERROR_FORMAT naming the file and line/field for
  // bad content.
  static std::shared_ptr<const MakeHumanModel> load(const std::string& body_dir,
                                                    MakeHumanRig rig = MakeHumanRig::cmu_mb);

  // The body for β: body-group mesh, skeleton with joints J(β), weights, β.
  Body body(const Eigen::VectorXd& beta) const;

  // The same with every base.obj vertex (19158, so indices are base.obj's, as
  // .mhclo garment files expect) and the triangles of the body and of every
  // helper group (joint cubes left out); weights cover all vertices. Pose it
  // like any body to move helper-tights / helper-skirt with the skin.
  Body body_with_helpers(const Eigen::VectorXd& beta) const;

  // All 19158 base.obj vertices shaped by β, in metres.
  Points3d shaped_vertices(const Eigen::VectorXd& beta) const;

  // Global joint positions (skeleton order) for shaped_vertices() output.
  Points3d joint_positions(const Points3d& shaped_vertices) const;

  // Non-zero target weights for β, by MANIFEST original path (e.g.
  // "height/male-young-averagemuscle-averageweight-maxheight.target").
  std::vector<std::pair<std::string, double>> target_weights(const Eigen::VectorXd& beta) const;

  MakeHumanRig rig() const { return rig_; }
  const std::string& directory() const { return dir_; }
  // Skeleton topology (names, parents); rest translations are those of the default β.
  const Skeleton& skeleton() const { return skeleton_; }
  // Weights of all 19158 vertices (helpers included), normalised per vertex.
  const SkinWeights& all_weights() const { return all_weights_; }
  // Vertices that had no weight in the rig's weights file (bound to the root joint).
  const std::vector<int32_t>& unweighted_vertices() const { return unweighted_; }
  // base.obj group names, and each group's vertices / triangles (indices into all 19158).
  std::vector<std::string> group_names() const;
  std::vector<int32_t> group_vertices(const std::string& group) const;
  Triangles group_triangles(const std::string& group) const;

  struct Impl;
  MakeHumanModel();
  ~MakeHumanModel();
  MakeHumanModel(const MakeHumanModel&) = delete;
  MakeHumanModel& operator=(const MakeHumanModel&) = delete;

 private:
  MakeHumanRig rig_ = MakeHumanRig::cmu_mb;
  std::string dir_;
  Skeleton skeleton_;
  SkinWeights all_weights_;
  std::vector<int32_t> unweighted_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pleat
