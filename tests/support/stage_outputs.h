#pragma once
// Positions of every frame of `poses` evaluated up to `stage`, for tests that
// compare the stages of one instance.
#include <vector>

#include "runtime/instance.h"

namespace pleat_test {

inline std::vector<float> evaluate_stage(pleat::runtime::Instance& instance,
                                         const pleat::runtime::PoseSequence& poses, int frames,
                                         pleat::runtime::Stage stage) {
  const size_t n = static_cast<size_t>(instance.vertex_count());
  std::vector<float> positions(static_cast<size_t>(frames) * n * 3);
  pleat::runtime::EvaluateOutputs out;
  out.positions = {positions.data(), n * 3};
  instance.evaluate(poses, 0, frames, stage, out);
  return positions;
}

}  // namespace pleat_test
