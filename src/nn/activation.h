#pragma once
// Element-wise activations applied in place on float buffers, on the kernel
// path of nn/kernel_path.h (nn/kernels/activation_eigen.cpp: Eigen's SIMD
// tanh and exp, within a few ulp of std::tanh / std::exp).
#include <cstdint>

#include "nn/kernel_params.h"
#include "nn/tensor.h"

namespace pleat::nn {

struct Activation {
  ActivationKind kind = ActivationKind::identity;
  // leaky_relu: negative slope; elu: alpha. Ignored by the others.
  float parameter = 0.01f;

  static Activation identity() { return {ActivationKind::identity, 0.0f}; }
  static Activation tanh() { return {ActivationKind::tanh, 0.0f}; }
  static Activation relu() { return {ActivationKind::relu, 0.0f}; }
  static Activation leaky_relu(float slope = 0.01f) { return {ActivationKind::leaky_relu, slope}; }
  static Activation elu(float alpha = 1.0f) { return {ActivationKind::elu, alpha}; }
};

void apply_activation(const Activation& act, float* data, Index count);

// A matrix view, row by row (rows may be strided).
void apply_activation(const Activation& act, MatrixRef m);

}  // namespace pleat::nn
