#pragma once
// Element-wise activations applied in place on float buffers. Eigen's array
// functions vectorise (tanh and exp use Eigen's SIMD approximations, within a
// few ulp of std::tanh / std::exp).
#include <Eigen/Core>
#include <cstdint>

#include "nn/tensor.h"

namespace pleat::nn {

enum class ActivationKind : int32_t { identity = 0, tanh = 1, relu = 2, leaky_relu = 3, elu = 4 };

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

inline void apply_activation(const Activation& act, float* data, Index count) {
  Eigen::Map<Eigen::ArrayXf> a(data, count);
  switch (act.kind) {
    case ActivationKind::identity: return;
    case ActivationKind::tanh: a = a.tanh(); return;
    case ActivationKind::relu: a = a.max(0.0f); return;
    case ActivationKind::leaky_relu: a = (a > 0.0f).select(a, a * act.parameter); return;
    case ActivationKind::elu: a = (a > 0.0f).select(a, act.parameter * (a.exp() - 1.0f)); return;
  }
}

// A matrix view, row by row (rows may be strided).
inline void apply_activation(const Activation& act, MatrixRef m) {
  if (act.kind == ActivationKind::identity) return;
  if (m.outerStride() == m.cols()) {
    apply_activation(act, m.data(), m.size());
    return;
  }
  for (Index r = 0; r < m.rows(); ++r) apply_activation(act, m.row(r).data(), m.cols());
}

}  // namespace pleat::nn
