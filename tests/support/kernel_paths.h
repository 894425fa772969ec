#pragma once
// Runs a test body once per kernel path this CPU runs (nn/kernel_path.h),
// restoring the default path afterwards, so both builds of the network's
// kernels meet the same reference.
#include <gtest/gtest.h>

#include <vector>

#include "nn/kernel_path.h"

namespace pleat::test {

// The paths this CPU runs, baseline first (the default is the last).
inline std::vector<nn::KernelPath> runnable_kernel_paths() {
  const nn::KernelPath initial = nn::kernel_path();
  std::vector<nn::KernelPath> paths;
  for (nn::KernelPath p : {nn::KernelPath::baseline, nn::KernelPath::avx2})
    if (nn::set_kernel_path(p)) paths.push_back(p);
  nn::set_kernel_path(initial);
  return paths;
}

template <typename Body>
void for_each_kernel_path(Body&& body) {
  const nn::KernelPath initial = nn::kernel_path();
  for (nn::KernelPath path : runnable_kernel_paths()) {
    ASSERT_TRUE(nn::set_kernel_path(path));
    SCOPED_TRACE(nn::kernel_path_name(path));
    body(path);
  }
  nn::set_kernel_path(initial);
}

}  // namespace pleat::test
