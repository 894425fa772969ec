#include "nn/mlp.h"

#include <algorithm>

namespace pleat::nn {

namespace {
constexpr const char* kMlpKind = "mlp";
}

Index Mlp::max_hidden_width() const {
  Index w = 0;
  for (size_t l = 0; l + 1 < layers.size(); ++l) w = std::max(w, layers[l].out_width());
  return w;
}

void Mlp::validate() const {
  if (layers.empty()) invalid(kMlpKind, name, "has no layers");
  for (size_t l = 0; l < layers.size(); ++l) {
    layers[l].validate();
    if (l > 0 && layers[l].in_width() != layers[l - 1].out_width())
      invalid(kMlpKind, name,
              "layer " + std::to_string(l) + " weight has " + std::to_string(layers[l].in_width()) +
                  " rows, expected " + std::to_string(layers[l - 1].out_width()) +
                  " (the previous layer's output width)");
  }
}

void mlp_forward(const Mlp& mlp, ConstMatrixRef x, MatrixRef y, MlpWorkspace& workspace) {
  if (mlp.layers.empty()) invalid(kMlpKind, mlp.name, "has no layers");
  check_shape(kMlpKind, mlp.name, "input x", x.rows(), x.cols(), -1, mlp.in_width());
  check_shape(kMlpKind, mlp.name, "output y", y.rows(), y.cols(), x.rows(), mlp.out_width());
  const Index rows = x.rows();
  const size_t half = static_cast<size_t>(rows) * static_cast<size_t>(mlp.max_hidden_width());
  check_scratch(kMlpKind, mlp.name, "MlpWorkspace", 2 * half, workspace.scratch().capacity());
  float* buffers[2] = {workspace.scratch().data(), workspace.scratch().data() + half};
  const size_t last = mlp.layers.size() - 1;
  for (size_t l = 0; l <= last; ++l) {
    const Dense& layer = mlp.layers[l];
    if (l > 0 && layer.in_width() != mlp.layers[l - 1].out_width()) mlp.validate();  // throws
    if (l == last) {
      if (l == 0) {
        dense_forward(layer, x, mlp.output_activation, y);
      } else {
        dense_forward(layer, view(buffers[(l - 1) % 2], rows, layer.in_width()), mlp.output_activation, y);
      }
    } else {
      MatrixMap out = view(buffers[l % 2], rows, layer.out_width());
      if (l == 0) {
        dense_forward(layer, x, mlp.hidden_activation, out);
      } else {
        dense_forward(layer, view(buffers[(l - 1) % 2], rows, layer.in_width()), mlp.hidden_activation, out);
      }
    }
  }
}

}  // namespace pleat::nn
