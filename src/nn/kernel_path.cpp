#include "nn/kernel_path.h"

#include <atomic>

namespace pleat::nn {
namespace {

bool cpu_runs(KernelPath path) {
  if (path == KernelPath::baseline) return true;
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

std::atomic<KernelPath>& active() {
  static std::atomic<KernelPath> path{cpu_runs(KernelPath::avx2) ? KernelPath::avx2 : KernelPath::baseline};
  return path;
}

}  // namespace

KernelPath kernel_path() {
  return active().load(std::memory_order_relaxed);
}

bool set_kernel_path(KernelPath path) {
  if (!cpu_runs(path)) return false;
  active().store(path);
  return true;
}

const char* kernel_path_name(KernelPath path) {
  return path == KernelPath::avx2 ? "avx2+fma" : "baseline (SSE2)";
}

}  // namespace pleat::nn
