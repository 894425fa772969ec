#pragma once
// Copies between the runtime's row-major float matrices and torch tensors.
#include <torch/torch.h>

#include "nn/tensor.h"

namespace pleat::training {

torch::Tensor to_tensor(const nn::MatrixRM& m);
torch::Tensor to_tensor(const nn::RowVector& v);
// Detached, converted to float32.
nn::MatrixRM to_matrix(const torch::Tensor& t);
nn::RowVector to_row(const torch::Tensor& t);

}  // namespace pleat::training
