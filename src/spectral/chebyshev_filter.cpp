#include "spectral/chebyshev_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pleat {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSamples = 2048;             // per band when measuring the damping ratio
constexpr Eigen::Index kColumnBlock = 64;  // columns filtered together

}  // namespace

ChebyshevFilter::ChebyshevFilter(double pass_edge, double stop_edge, double ratio, int max_degree)
    : pass_edge_(pass_edge), stop_edge_(stop_edge) {
  int degree = 8;
  for (;;) {
    design(degree);
    ratio_ = measure_ratio();
    if (ratio_ <= ratio || degree >= max_degree) break;
    degree = std::min(max_degree, degree + std::max(4, degree / 4));
  }
}

void ChebyshevFilter::design(int degree) {
  // Step h(t) = 1 for t < t_c, t = x - 1, cut halfway between the edges.
  // Chebyshev coefficients: c_0 = (pi - theta_c) / pi, c_j = -2 sin(j theta_c) / (j pi),
  // with theta_c = acos(t_c); Jackson kernel g_j (Weisse et al. 2006, eq. 71).
  const double theta_c = std::acos(std::clamp(0.5 * (pass_edge_ + stop_edge_) - 1.0, -1.0, 1.0));
  const double m = degree + 1.0;
  coefficients_.assign(static_cast<size_t>(degree) + 1, 0.0);
  for (int j = 0; j <= degree; ++j) {
    const double c = j == 0 ? (kPi - theta_c) / kPi : -2.0 * std::sin(j * theta_c) / (j * kPi);
    const double g = ((m - j) * std::cos(kPi * j / m) + std::sin(kPi * j / m) / std::tan(kPi / m)) / m;
    coefficients_[static_cast<size_t>(j)] = c * g;
  }
}

double ChebyshevFilter::evaluate(double x) const {
  // Clenshaw recurrence.
  const double t = x - 1.0;
  double b1 = 0.0, b2 = 0.0;
  for (size_t j = coefficients_.size() - 1; j >= 1; --j) {
    const double b0 = coefficients_[j] + 2.0 * t * b1 - b2;
    b2 = b1;
    b1 = b0;
  }
  return coefficients_[0] + t * b1 - b2;
}

double ChebyshevFilter::measure_ratio() const {
  double pass_min = std::numeric_limits<double>::infinity(), stop_max = 0.0;
  for (int i = 0; i <= kSamples; ++i) {
    pass_min = std::min(pass_min, evaluate(pass_edge_ * i / kSamples));
    stop_max = std::max(stop_max, std::abs(evaluate(stop_edge_ + (2.0 - stop_edge_) * i / kSamples)));
  }
  return pass_min > 0.0 ? stop_max / pass_min : std::numeric_limits<double>::infinity();
}

void ChebyshevFilter::apply(const Eigen::SparseMatrix<double>& laplacian, const Eigen::MatrixXd& in,
                            Eigen::MatrixXd* out) const {
  using RowBlock = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  // Row-major operands turn each sparse product into row axpys over a block
  // of columns: vectorised and cache-resident (several times faster than
  // column-major sparse * dense here).
  const Eigen::SparseMatrix<double, Eigen::RowMajor> shifted =
      laplacian - Eigen::SparseMatrix<double>(Eigen::VectorXd::Ones(laplacian.rows()).asDiagonal());
  out->resize(in.rows(), in.cols());
  // Three-term recurrence T_{j+1}(t) = 2 t T_j(t) - T_{j-1}(t), t = L - I, per block.
  RowBlock previous, current, next, acc;
  for (Eigen::Index first = 0; first < in.cols(); first += kColumnBlock) {
    const Eigen::Index cols = std::min(kColumnBlock, in.cols() - first);
    previous = in.middleCols(first, cols);
    acc = coefficients_[0] * previous;
    if (coefficients_.size() > 1) {
      current.noalias() = shifted * previous;
      acc += coefficients_[1] * current;
    }
    for (size_t j = 2; j < coefficients_.size(); ++j) {
      next.noalias() = shifted * current;
      next = 2.0 * next - previous;
      acc += coefficients_[j] * next;
      std::swap(previous, current);
      std::swap(current, next);
    }
    out->middleCols(first, cols) = acc;
  }
}

}  // namespace pleat
