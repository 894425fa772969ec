#pragma once
// Copies between the runtime's row-major float matrices and torch tensors.
#include <torch/torch.h>

#include "core/mesh.h"
#include "nn/tensor.h"

namespace pleat::training {

torch::Tensor to_tensor(const nn::MatrixRM& m);
torch::Tensor to_tensor(const nn::RowVector& v);
// Detached, converted to float32.
nn::MatrixRM to_matrix(const torch::Tensor& t);
nn::RowVector to_row(const torch::Tensor& t);
// An N x 3 tensor as points (detached, float64).
Points3d points_of(const torch::Tensor& x);

}  // namespace pleat::training
