#include "tensors.h"

namespace pleat::training {

torch::Tensor to_tensor(const nn::MatrixRM& m) {
  return torch::from_blob(const_cast<float*>(m.data()), {m.rows(), m.cols()}, torch::kFloat32).clone();
}

torch::Tensor to_tensor(const nn::RowVector& v) {
  return torch::from_blob(const_cast<float*>(v.data()), {v.size()}, torch::kFloat32).clone();
}

nn::MatrixRM to_matrix(const torch::Tensor& t) {
  const torch::Tensor c = t.detach().to(torch::kFloat32).contiguous();
  return Eigen::Map<const nn::MatrixRM>(c.data_ptr<float>(), c.size(0), c.size(1));
}

nn::RowVector to_row(const torch::Tensor& t) {
  const torch::Tensor c = t.detach().to(torch::kFloat32).contiguous();
  return Eigen::Map<const nn::RowVector>(c.data_ptr<float>(), c.numel());
}

Points3d points_of(const torch::Tensor& x) {
  const torch::Tensor c = x.detach().to(torch::kFloat64).contiguous();
  return Eigen::Map<const Points3d>(c.data_ptr<double>(), c.size(0), 3);
}

}  // namespace pleat::training
