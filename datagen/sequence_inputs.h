#pragma once
// Everything one simulation starts from, computed in pleat: the shaped body,
// the garment fitted to it (.mhclo), the clip retargeted onto it with a
// settling lead-in, the posed body and the skinned garment for every frame,
// and the pinned vertices.
#include <memory>
#include <vector>

#include "body/body.h"
#include "body/makehuman.h"
#include "body/mhclo.h"
#include "body/motion_ops.h"
#include "config.h"
#include "plan.h"

namespace pleat::datagen {

// What every job shares, loaded once (read-only afterwards, so workers may
// use it from several threads).
struct Assets {
  std::shared_ptr<const MakeHumanModel> model;
  std::vector<Body> bodies;                  // per shape
  std::vector<Points3d> shaped;              // per shape: all base.obj vertices (what .mhclo indexes)
  std::vector<ClothesBinding> bindings;      // per garment
  std::vector<Triangles> garment_triangles;  // per garment, indices of its OBJ's "v" lines
  ClothesBinding collider;                   // config.collider's proxy (no vertices: the body collides)
  Triangles collider_triangles;
  std::vector<Motion> motions;  // per clip, resampled to the frame rate (source skeleton)
  std::vector<JointMap> maps;   // per clip (no entries: pair joints by equal names)
};

// Throws the readers' errors (naming file and line) and
// PLEAT_ERROR_INVALID_ARGUMENT naming the shape entry or garment at fault.
Assets load_assets(const Config& config);

struct SequenceInputs {
  const Body* body = nullptr;
  TriMesh garment_rest;  // fitted to the shaped body, rest pose
  Motion motion;         // lead-in + segment, on the body's skeleton
  int64_t lead_in = 0;   // frames to discard: rest_frames + blend_frames
  Eigen::Vector3d root_offset =
      Eigen::Vector3d::Zero();         // subtracted from the root: the lead-in starts at the rest root
  std::vector<float> body_frames;      // every frame x body vertices x 3
  std::vector<float> garment_skinned;  // every frame x garment vertices x 3 (nearest-vertex LBS)
  std::vector<int32_t> pinned;
  // config.collider's proxy, fitted and skinned like the garment; empty when
  // the body itself collides.
  TriMesh collider_rest;
  std::vector<float> collider_frames;  // every frame x collider vertices x 3
};

SequenceInputs prepare_sequence(const Config& config, const Assets& assets, const Job& job);

// `clip` preceded by rest_frames standing still in the rest pose (identity
// rotations) and blend_frames easing (smoothstep) from the rest pose towards
// the clip's first frame: slerped rotations, and a root whose velocity eases
// from 0 to the clip's initial velocity (mean over its first 4 frames), so the
// cloth is not jolted into a walk. The root stands still at first - v T / 2
// (T the blend's duration) and arrives at the clip's first position. The
// clip's frames follow unchanged.
Motion with_lead_in(const Motion& clip, int64_t rest_frames, int64_t blend_frames);

// Where clothes hold on, per piece (connected component) of the rest garment:
// the vertices of its top band (within `band` of its highest point: a
// waistband, collar, shoulders) that are closer than `distance` to a rest body
// vertex, or the whole band if none is that close (the piece hangs from it).
// Pieces of at most kRigidPieceVertices vertices (buttons, loops) are pinned
// whole. distance <= 0 pins nothing.
constexpr int32_t kRigidPieceVertices = 64;
std::vector<int32_t> pinned_vertices(const Body& body, const TriMesh& garment, double distance, double band);

// A longer garment from a bound one: with y0 the lowest rest height and y1 =
// y0 + below (y_max - y0), every vertex under y1 moves to
// y1 - factor (y1 - y), the rest stays. The hem drops by (factor - 1)(y1 - y0)
// and keeps its width; only heights change, so a skirt hangs as it was cut,
// longer. below in (0, 1], factor >= 1.
void stretch_hem(Points3d* vertices, double below, double factor);

}  // namespace pleat::datagen
