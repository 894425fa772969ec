#pragma once
// Jackson-damped Chebyshev expansion of a step on [0, 2] (the spectrum of
// L_norm): ~1 on [0, pass_edge], ~0 on [stop_edge, 2], smooth and free of
// Gibbs overshoot between, so filtered subspace iteration converges to the
// eigenvectors below pass_edge.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

namespace pleat {

class ChebyshevFilter {
 public:
  // Picks the lowest degree whose damping ratio max|p| on [stop_edge, 2] /
  // min p on [0, pass_edge] is at most `ratio` (capped at max_degree).
  ChebyshevFilter(double pass_edge, double stop_edge, double ratio, int max_degree);

  int degree() const { return static_cast<int>(coefficients_.size()) - 1; }
  double ratio() const { return ratio_; }
  double evaluate(double x) const;
  // out = p(L) in, column block by column block (bounded memory).
  void apply(const Eigen::SparseMatrix<double>& laplacian, const Eigen::MatrixXd& in,
             Eigen::MatrixXd* out) const;

 private:
  void design(int degree);
  double measure_ratio() const;

  double pass_edge_, stop_edge_;
  std::vector<double> coefficients_;  // damped Chebyshev coefficients in t = x - 1
  double ratio_ = 1.0;
};

}  // namespace pleat
