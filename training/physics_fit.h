#pragma once
// How well the trainer's physics terms explain a simulator's frames, and the
// weights that explain them best. The incremental potential
//   inertia + k_g gravity + k_s stretch + k_sh shear + k_b bending
// is stationary at a simulated frame when its forces balance: m a = the sum
// of the weighted terms' forces. Over the free vertices of many frames (away
// from the body, whose contact force no term models), the weights that make
// the simulated frames most nearly stationary are a linear least-squares fit.
// Self-supervised training (inertia on unsimulated motion) would need
// them: a physics term with the wrong stiffness pulls the cloth away from
// what the simulator would do (decision 0027).
#include <torch/torch.h>

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>

#include "dataset.h"
#include "losses.h"

namespace pleat::training {

struct PhysicsFit {
  // Free fit: gravity, stretch, shear and bending per unit inertia weight.
  // Gravity comes out 1 where the simulator's forces are these terms' (its
  // gravity and masses agree with the losses').
  std::map<std::string, double> weights;
  // The same with gravity held at 1, the physical value: the elastic
  // weights that match the simulator, where the residual says they do.
  std::map<std::string, double> elastic_weights;
  // |m a - Σ k f| / |m a| over the rows fitted: free fit, gravity held at 1,
  // and gravity alone (the elastic terms 0: free fall).
  double residual = 0.0, elastic_residual = 0.0, gravity_only_residual = 0.0;
  int64_t frames = 0;
  int64_t rows = 0;  // free vertex coordinates fitted
};

class PhysicsFitter {
 public:
  // frames: T x N x 3 simulated positions, body: T x Nb x 3 posed body (Nb may
  // be 0: every vertex free). Frames 2, 2 + stride, ... are fitted; a vertex
  // is free when it is more than `contact_cm` from the nearest body vertex.
  void add(const GarmentGeometry& g, const torch::Tensor& frames, const torch::Tensor& body,
           double frame_rate, int64_t frame_stride = 1, double contact_cm = 2.0);
  // Fails with PLEAT_ERROR_INVALID_ARGUMENT when nothing was added.
  PhysicsFit solve() const;

 private:
  static constexpr int kColumns = 5;  // inertia, gravity, stretch, shear, bending
  Eigen::Matrix<double, kColumns, kColumns> normal_ = Eigen::Matrix<double, kColumns, kColumns>::Zero();
  int64_t frames_ = 0, rows_ = 0;
};

// Every sequence of `data`, as PhysicsFitter::add.
PhysicsFit fit_physics(const Dataset& data, int64_t frame_stride = 1, double contact_cm = 2.0);

}  // namespace pleat::training
