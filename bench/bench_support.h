#pragma once
// Timing shared by the benchmarks: the median of repeated runs after one
// warm-up (page faults, BLAS and pool threads starting).
#include <algorithm>
#include <chrono>
#include <functional>
#include <vector>

namespace pleat_bench {

inline double median_seconds(const std::function<void()>& f, int reps) {
  f();
  std::vector<double> t;
  for (int r = 0; r < reps; ++r) {
    const auto s = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - s).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace pleat_bench
