#pragma once
// Runs a test body once per kernel path this CPU runs (nn/kernel_path.h),
// restoring the default path afterwards, so both builds of the network's
// kernels meet the same reference.
#include <gtest/gtest.h>

#include <vector>

#include "nn/kernel_path.h"

namespace pleat_test {

// The paths this CPU runs, baseline first (the default is the last).
inline std::vector<pleat::nn::KernelPath> runnable_kernel_paths() {
  const pleat::nn::KernelPath initial = pleat::nn::kernel_path();
  std::vector<pleat::nn::KernelPath> paths;
  for (pleat::nn::KernelPath p : {pleat::nn::KernelPath::baseline, pleat::nn::KernelPath::avx2})
    if (pleat::nn::set_kernel_path(p)) paths.push_back(p);
  pleat::nn::set_kernel_path(initial);
  return paths;
}

template <typename Body>
void for_each_kernel_path(Body&& body) {
  const pleat::nn::KernelPath initial = pleat::nn::kernel_path();
  for (pleat::nn::KernelPath path : runnable_kernel_paths()) {
    ASSERT_TRUE(pleat::nn::set_kernel_path(path));
    SCOPED_TRACE(pleat::nn::kernel_path_name(path));
    body(path);
  }
  pleat::nn::set_kernel_path(initial);
}

}  // namespace pleat_test
