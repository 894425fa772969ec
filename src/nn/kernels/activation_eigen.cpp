// Element-wise activations in place, compiled once per instruction set
// (nn/kernels/eigen_renamed.h; nn/activation.h picks one at run time). tanh
// and exp are Eigen's SIMD approximations, within a few ulp of std::tanh /
// std::exp; the AVX2 build evaluates eight lanes at a time.
#include "nn/kernels/eigen_renamed.h"
// Only plain declarations from pleat: nothing the linker could merge.
#include "nn/kernels/entry_points.h"

namespace pleat::nn::kernels {

void PLEAT_KERNEL_ENTRY(activate)(ActivationKind kind, float parameter, float* data, long count) {
  Eigen::Map<Eigen::ArrayXf> a(data, count);
  switch (kind) {
    case ActivationKind::identity: return;
    case ActivationKind::tanh: a = a.tanh(); return;
    case ActivationKind::relu: a = a.max(0.0f); return;
    case ActivationKind::leaky_relu: a = (a > 0.0f).select(a, a * parameter); return;
    case ActivationKind::elu: a = (a > 0.0f).select(a, parameter * (a.exp() - 1.0f)); return;
  }
}

}  // namespace pleat::nn::kernels
