#pragma once
// Multi-layer perceptron: a chain of Dense layers, one activation for the
// hidden layers and its own for the last (e.g. tanh / tanh for the body
// encoder, tanh / identity for a regression head).
#include <string>
#include <vector>

#include "nn/dense.h"

namespace pleat::nn {

struct Mlp {
  std::string name = "mlp";
  std::vector<Dense> layers;
  Activation hidden_activation = Activation::tanh();
  Activation output_activation = Activation::identity();

  Index in_width() const { return layers.empty() ? 0 : layers.front().in_width(); }
  Index out_width() const { return layers.empty() ? 0 : layers.back().out_width(); }
  // Widest hidden output (what the workspace holds per row); 0 for one layer.
  Index max_hidden_width() const;
  // Throws unless there is at least one layer and widths chain.
  void validate() const;
};

// Two ping-pong buffers of rows x max_hidden_width.
class MlpWorkspace {
 public:
  void reserve(const Mlp& mlp, Index rows) {
    scratch_.reserve(2 * static_cast<size_t>(rows) * static_cast<size_t>(mlp.max_hidden_width()));
  }
  Scratch& scratch() { return scratch_; }

 private:
  Scratch scratch_;
};

// x: rows x in_width, y: rows x out_width (must not alias x). Allocates
// nothing once the workspace is reserved for at least `rows` rows (throws
// otherwise).
void mlp_forward(const Mlp& mlp, ConstMatrixRef x, MatrixRef y, MlpWorkspace& workspace);

}  // namespace pleat::nn
