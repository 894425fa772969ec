#include "nn/dense.h"

#include "nn/gemm.h"

namespace pleat::nn {

namespace {
constexpr const char* kDenseKind = "dense layer";
}

void Dense::validate() const {
  if (weight.size() == 0) invalid(kDenseKind, name, "weight is empty");
  if (bias.size() != 0) check_shape(kDenseKind, name, "bias", 1, bias.size(), 1, out_width());
  if (!weight.allFinite() || !bias.allFinite())
    invalid(kDenseKind, name, "weight or bias holds a NaN or infinite value");
}

void dense_forward(const Dense& layer, ConstMatrixRef x, const Activation& act, MatrixRef y) {
  check_shape(kDenseKind, layer.name, "input x", x.rows(), x.cols(), -1, layer.in_width());
  check_shape(kDenseKind, layer.name, "output y", y.rows(), y.cols(), x.rows(), layer.out_width());
  if (layer.bias.size() != 0 && layer.bias.size() != layer.out_width())
    check_shape(kDenseKind, layer.name, "bias", 1, layer.bias.size(), 1, layer.out_width());
  gemm(x, layer.weight, y);
  for (Index r = 0; r < y.rows(); ++r) {
    float* row = y.row(r).data();
    if (layer.bias.size() != 0) {
      Eigen::Map<Eigen::ArrayXf>(row, y.cols()) += layer.bias.transpose().array();
    }
    apply_activation(act, row, y.cols());
  }
}

}  // namespace pleat::nn
