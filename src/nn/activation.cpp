#include "nn/activation.h"

#include "nn/kernel_path.h"
#include "nn/kernels/entry_points.h"

namespace pleat::nn {

void apply_activation(const Activation& act, float* data, Index count) {
  if (act.kind == ActivationKind::identity) return;
  const auto run = kernel_path() == KernelPath::avx2 ? kernels::activate_avx2 : kernels::activate_baseline;
  run(act.kind, act.parameter, data, count);
}

void apply_activation(const Activation& act, MatrixRef m) {
  if (act.kind == ActivationKind::identity) return;
  if (m.outerStride() == m.cols()) {
    apply_activation(act, m.data(), m.size());
    return;
  }
  for (Index r = 0; r < m.rows(); ++r) apply_activation(act, m.row(r).data(), m.cols());
}

}  // namespace pleat::nn
