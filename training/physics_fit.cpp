#include "physics_fit.h"

#include <Eigen/Cholesky>
#include <array>
#include <cmath>

#include "capi/pleat.h"
#include "core/error.h"
#include "core/nearest_points.h"
#include "tensors.h"

namespace pleat::training {
namespace {

constexpr std::array<const char*, 4> kTerms = {"gravity", "stretch", "shear", "bending"};

// Whether each vertex of x (N x 3) is further than `contact` (m) from every
// body vertex (Nb x 3).
torch::Tensor free_vertices(const torch::Tensor& x, const torch::Tensor& body, double contact) {
  if (body.size(0) == 0) return torch::ones({x.size(0)}, torch::kBool);
  const std::vector<int32_t> nearest = nearest_points(points_of(body), points_of(x));
  const torch::Tensor index =
      torch::tensor(std::vector<int64_t>(nearest.begin(), nearest.end()), torch::kInt64);
  return (x - body.index_select(0, index)).norm(2, -1) > contact;
}

}  // namespace

void PhysicsFitter::add(const GarmentGeometry& g, const torch::Tensor& frames, const torch::Tensor& body,
                        double frame_rate, int64_t frame_stride, double contact_cm) {
  if (frame_stride < 1) fail(PLEAT_ERROR_INVALID_ARGUMENT, "fit_physics: frame_stride must be >= 1");
  const torch::Tensor simulated = frames.to(torch::kFloat64);
  for (int64_t t = 2; t < simulated.size(0); t += frame_stride) {
    const torch::Tensor x = simulated[t].unsqueeze(0).requires_grad_(true);
    const torch::Tensor energies[kColumns] = {
        inertia_loss(g, x, simulated[t - 1].unsqueeze(0), simulated[t - 2].unsqueeze(0), frame_rate),
        gravity_loss(g, x), stretch_loss(g, x), shear_loss(g, x), bending_loss(g, x)};
    const torch::Tensor free = free_vertices(simulated[t], body[t].to(torch::kFloat64), contact_cm / 100);
    std::vector<torch::Tensor> columns;
    for (const torch::Tensor& e : energies)
      columns.push_back(
          torch::autograd::grad({e}, {x}, {}, /*retain_graph=*/true)[0][0].index({free}).flatten());
    const torch::Tensor a = torch::stack(columns, 1);  // rows x columns
    const torch::Tensor gram = torch::matmul(a.t(), a).contiguous();
    normal_ +=
        Eigen::Map<const Eigen::Matrix<double, kColumns, kColumns, Eigen::RowMajor>>(gram.data_ptr<double>());
    rows_ += a.size(0);
    ++frames_;
  }
}

PhysicsFit PhysicsFitter::solve() const {
  if (rows_ == 0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         "fit_physics: no frame after the second with a vertex away from the body");
  using Vector = Eigen::Matrix<double, kColumns, 1>;
  // |A k| / |A e_0| for a weight vector k (inertia first), from the normal equations.
  const auto residual = [&](const Vector& k) {
    return std::sqrt(std::max(0.0, k.dot(normal_ * k)) / normal_(0, 0));
  };
  PhysicsFit fit;
  fit.frames = frames_;
  fit.rows = rows_;
  // Free: min_k |g_0 + Σ_j k_j g_j|².
  Vector free = Vector::Zero();
  free(0) = 1;
  free.tail<kColumns - 1>() = normal_.bottomRightCorner<kColumns - 1, kColumns - 1>().ldlt().solve(
      -normal_.col(0).tail<kColumns - 1>());
  // Gravity held at 1: min_k |g_0 + g_1 + Σ_{j>1} k_j g_j|².
  Vector elastic = Vector::Zero();
  elastic(0) = elastic(1) = 1;
  elastic.tail<kColumns - 2>() = normal_.bottomRightCorner<kColumns - 2, kColumns - 2>().ldlt().solve(
      -(normal_.col(0) + normal_.col(1)).tail<kColumns - 2>());
  Vector gravity_only = Vector::Zero();
  gravity_only(0) = gravity_only(1) = 1;
  fit.residual = residual(free);
  fit.elastic_residual = residual(elastic);
  fit.gravity_only_residual = residual(gravity_only);
  for (size_t j = 0; j < kTerms.size(); ++j) {
    fit.weights[kTerms[j]] = free(static_cast<int>(j) + 1);
    fit.elastic_weights[kTerms[j]] = elastic(static_cast<int>(j) + 1);
  }
  return fit;
}

PhysicsFit fit_physics(const Dataset& data, int64_t frame_stride, double contact_cm) {
  PhysicsFitter fitter;
  for (const TrainingSequence& s : data.sequences())
    fitter.add(GarmentGeometry(*s.garment), s.truth, s.body_positions, s.meta.frame_rate, frame_stride,
               contact_cm);
  return fitter.solve();
}

}  // namespace pleat::training
