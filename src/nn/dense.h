#pragma once
// Fully connected layer over a batch of rows: y = act(x W + b).
#include <string>

#include "nn/activation.h"
#include "nn/tensor.h"

namespace pleat::nn {

struct Dense {
  std::string name = "dense";
  MatrixRM weight;  // in x out (= PyTorch nn.Linear.weight transposed)
  RowVector bias;   // out, or empty for no bias

  Index in_width() const { return weight.rows(); }
  Index out_width() const { return weight.cols(); }
  // Throws when the bias does not match the weight or a parameter is not finite.
  void validate() const;
};

// x: rows x in, y: rows x out (may be a view into a workspace; must not
// alias x). One GEMM (OpenBLAS for large sizes), then bias and activation in
// one pass. Allocates nothing.
void dense_forward(const Dense& layer, ConstMatrixRef x, const Activation& act, MatrixRef y);

}  // namespace pleat::nn
