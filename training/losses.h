#pragma once
// The training losses of the paper (§III-C, DESIGN §6) on batches of frames.
// Positions are B x N x 3 tensors in metres; every loss is averaged over the
// frames of the batch and returned unweighted (the schedule applies k_*).
// Units follow the paper: the vertex losses are in metres (k_v = 100 makes
// them centimetres), the collision margins and Eq. 15's distances in cm.
#include <torch/torch.h>

#include <vector>

#include "garment/garment.h"
#include "spectral/bands.h"

namespace pleat::training {

// The curvature loss weighs a vertex by this area over its own (m^2): about a
// vertex's area at the 2-3 cm edges of the MakeHuman garments, so their weights
// are near 1 and curvature's k keeps its scale.
inline constexpr double kCurvatureReferenceArea = 3e-4;

// Everything the losses need from the rest garment, as tensors.
struct GarmentGeometry {
  explicit GarmentGeometry(const Garment& garment, double density = 0.15 /* kg/m², cotton */);

  torch::Tensor rest;          // N x 3
  torch::Tensor edges;         // E x 2 (int64), unique mesh edges
  torch::Tensor triangles;     // F x 3 (int64)
  torch::Tensor rest_inverse;  // F x 2 x 2: inverse of the rest edge matrix in each face's own 2D frame
  torch::Tensor rest_areas;    // F
  torch::Tensor masses;        // N: density x one third of the incident rest area
  torch::Tensor hinges;        // H x 4 (int64): edge (a, b) and the opposite corners (c, d) of its two faces
  torch::Tensor hinge_rest;    // H: rest dihedral angle
  torch::Tensor hinge_weight;  // H: 3 |e|² / (A1 + A2) (discrete shells)
  torch::Tensor interior;      // I (int64): vertices with a closed fan, where E_curv is measured
  torch::Tensor curvature_weight;  // I: kCurvatureReferenceArea / rest vertex area (curvature_loss)
  torch::Tensor edge_lengths;      // E: rest length of each edge
  Csr geodesic;                    // rest geodesic neighbourhoods (prepared garment; empty otherwise)
};

// Frequency bands of the prepared garment as a linear projection of errors:
// low(e), mid(e), high(e) = e - low - mid, exactly split_bands' definition
// (random-walk or symmetric form, the basis's own cuts).
class BandProjector {
 public:
  explicit BandProjector(const BandBasis<float>& basis);
  // e: B x N x 3 -> {low, mid, high}, each B x N x 3.
  std::array<torch::Tensor, 3> split(const torch::Tensor& e) const;

 private:
  torch::Tensor low_, mid_, scale_;  // N x l, N x (m - l), N x 1 (sqrt degree; ones for symmetric)
};

// Eq. 11-14: L_lv + k_mv L_mv + k_hv L_hv with L_xv = 1/N Σ_i ||band_x(x - x_GT)_i||₂
// (k_v outside). The three band terms come back separately too.
struct VertexLoss {
  torch::Tensor total, low, mid, high;
};
VertexLoss frequency_vertex_loss(const BandProjector& bands, const torch::Tensor& x,
                                 const torch::Tensor& truth, double k_mid, double k_high);
// The same without frequency division: 1/N Σ_i ||x_i - x_i^GT||₂.
torch::Tensor vertex_loss(const torch::Tensor& x, const torch::Tensor& truth);

// Mean over edges of |l_e - l_e^GT| / l_e^GT: E_edge's definition as a
// fraction (edges of zero true length skipped), so k_e weighs a relative
// stretch against the vertex loss in centimetres (decision 0005).
torch::Tensor edge_loss(const GarmentGeometry& g, const torch::Tensor& x, const torch::Tensor& truth);

// Mean over interior vertices of w |Σθ - Σθ^GT|, the corner angles summed
// at each vertex (radians), w = 1 / the rest vertex area, divided by its
// mean over the interior vertices: E_curv's own weighting (it divides the
// angle defect by the vertex's area), scaled to a mean weight of 1 so that
// k keeps its size across garments (decisions 0005, 0006).
torch::Tensor curvature_loss(const GarmentGeometry& g, const torch::Tensor& x, const torch::Tensor& truth);

// Roughness of the network's correction to the body's skinning: mean over
// frames and mesh edges (i, j) of Σ_s |(w_is - w_js) - (p_is - p_js)|, with
// w the predicted skinning weights (B x N x S) and p the weights of the
// skinning prior alone (N x S; undefined: no prior, p = 0). Zero while the
// correction is the same at both ends of every edge, whatever its size: it
// is the weights' jumps between neighbours that bend the skinned cloth and
// set E_curv at the skinning stage (decision 0006).
torch::Tensor skinning_smoothness_loss(const GarmentGeometry& g, const torch::Tensor& weights,
                                       const torch::Tensor& prior_weights);

// Roughness of an offset field the network adds (B x N x 3: the blend
// shapes in rest space, or the refinement's Δ): mean over frames and mesh
// edges (i, j) of |o_i - o_j| / |rest edge|, the field's slope along the
// edge. A wrinkle a few centimetres wide has slopes of a few tenths; offsets
// that differ between the vertices of millimetre faces have slopes of
// several, and those are what E_curv, which divides the angle defect by the
// vertex area, measures most (decision 0007). Edges of zero rest length are
// skipped.
torch::Tensor offset_smoothness_loss(const GarmentGeometry& g, const torch::Tensor& offsets);

// Mean over faces of 1 - cos(n_f, n_f^GT).
torch::Tensor normal_loss(const GarmentGeometry& g, const torch::Tensor& x, const torch::Tensor& truth);

// Garment-body collision (SNUG): mean over vertices of max(margin - d_i, 0)³,
// d_i = (x_i - p_i)·n_i in cm, p_i the nearest posed body vertex and n_i its
// unit normal. body, body_normals: B x Nb x 3. margin in cm.
torch::Tensor collision_loss(const torch::Tensor& x, const torch::Tensor& body,
                             const torch::Tensor& body_normals, double margin_cm = 0.4);

// Eq. 15: 1/ΣK Σ K_ij exp(-λ d_ij), d in cm, K_ij = 1 for pairs whose rest
// geodesic distance exceeds the prepared radius (not neighbours in
// g.geodesic) and whose current distance is below `threshold_cm`. 0 when no
// pair qualifies.
torch::Tensor self_collision_loss(const GarmentGeometry& g, const torch::Tensor& x, double lambda = 8.0,
                                  double threshold_cm = 2.0);

// The inertia term of one implicit-Euler step (SNUG, HOOD): mean over frames of
// Σ_i m_i |x_i - 2 p_i + q_i|² / (2 h²), with p, q the positions one and two
// frames before and h = 1 / frame_rate (J). With gravity and the elastic
// terms it is the incremental potential whose minimum is the next frame of
// a simulation; fit_physics (physics_fit.h) asks whether a simulator's
// frames are such minima. No schedule weighs it (decision 0027).
// x, previous, before: B x N x 3.
torch::Tensor inertia_loss(const GarmentGeometry& g, const torch::Tensor& x, const torch::Tensor& previous,
                           const torch::Tensor& before, double frame_rate);

// Gravitational potential relative to the rest pose: Σ_i m_i 9.81 (y_i - ȳ_i) (J).
torch::Tensor gravity_loss(const GarmentGeometry& g, const torch::Tensor& x);

// Baraff-Witkin membrane terms per face, area-weighted sums over faces
// (F = deformation gradient, w_u, w_v its columns in the rest 2D frame):
// stretch Σ A ((|w_u| - 1)² + (|w_v| - 1)²), shear Σ A (w_u·w_v)².
torch::Tensor stretch_loss(const GarmentGeometry& g, const torch::Tensor& x);
torch::Tensor shear_loss(const GarmentGeometry& g, const torch::Tensor& x);

// Discrete-shells bending: Σ_hinges w (θ - θ_rest)², θ the dihedral angle.
torch::Tensor bending_loss(const GarmentGeometry& g, const torch::Tensor& x);

}  // namespace pleat::training
