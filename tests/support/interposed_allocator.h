#pragma once
// Interposes the C allocator in the test binary whose one source file
// includes this header: every operator new, Eigen matrix and std::vector,
// in the test and in libpleat.so, ends in these functions. It counts
// allocations and can make one of them fail, returning NULL as the system
// does when memory runs out. AddressSanitizer brings its own allocator, so
// under it nothing is interposed (kAllocatorInterposed is false).
#include <atomic>
#include <cerrno>
#include <cstddef>

#include "support/sanitizers.h"

namespace pleat_test {

constexpr bool kAllocatorInterposed = !kUnderAddressSanitizer;

namespace detail {
inline std::atomic<long> allocations{0};
inline std::atomic<long> failing{-1};  // the allocation number that fails; -1: none

// Counts one allocation; true when it is the one armed to fail.
inline bool allocation_fails() {
  const long n = allocations.fetch_add(1, std::memory_order_relaxed);
  return n == failing.load(std::memory_order_relaxed);
}
}  // namespace detail

inline long allocation_count() {
  return detail::allocations.load();
}

// The n-th allocation from now (0: the next) returns NULL; -1 disarms.
inline void fail_allocation(long n) {
  detail::failing.store(n < 0 ? -1 : detail::allocations.load() + n);
}

}  // namespace pleat_test

#if !defined(PLEAT_TEST_ASAN)
extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void* __libc_memalign(size_t, size_t);
void* malloc(size_t size) {
  if (pleat_test::detail::allocation_fails()) return nullptr;
  return __libc_malloc(size);
}
void* calloc(size_t count, size_t size) {
  if (pleat_test::detail::allocation_fails()) return nullptr;
  return __libc_calloc(count, size);
}
void* realloc(void* p, size_t size) {
  if (pleat_test::detail::allocation_fails()) return nullptr;
  return __libc_realloc(p, size);
}
void* aligned_alloc(size_t alignment, size_t size) {
  if (pleat_test::detail::allocation_fails()) return nullptr;
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, size_t alignment, size_t size) {
  if (pleat_test::detail::allocation_fails()) return ENOMEM;
  *out = __libc_memalign(alignment, size);
  return *out ? 0 : ENOMEM;
}
}
#endif
