#pragma once
// For the target whose loader runs assimp (fuzz_fbx; glTF is read by pleat
// since 2026-12-05 and its targets run with the real operator new):
// assimp 5.2 sizes arrays from counts in the file before it checks them
// against the file (an accessor of 2^32 - 2 elements asks for 64 GB). In a
// real process that operator new throws std::bad_alloc, which assimp turns
// into a failed import and pleat into PLEAT_ERROR_FORMAT; under ASan a refused
// operator new aborts instead and would end every campaign at the first such
// file. This replacement restores the real behaviour above 1 GiB. Memory still
// comes from ASan's malloc, so every access is still checked.
#include <cstdlib>
#include <new>

namespace pleat_fuzz {
constexpr size_t kLargestAllocation = size_t{1} << 30;
inline void* bounded_allocation(size_t bytes) {
  void* p = bytes <= kLargestAllocation ? std::malloc(bytes ? bytes : 1) : nullptr;
  if (!p) throw std::bad_alloc();
  return p;
}
}  // namespace pleat_fuzz

void* operator new(size_t bytes) {
  return pleat_fuzz::bounded_allocation(bytes);
}
void* operator new[](size_t bytes) {
  return pleat_fuzz::bounded_allocation(bytes);
}
void* operator new(size_t bytes, const std::nothrow_t&) noexcept {
  return bytes <= pleat_fuzz::kLargestAllocation ? std::malloc(bytes ? bytes : 1) : nullptr;
}
void* operator new[](size_t bytes, const std::nothrow_t&) noexcept {
  return bytes <= pleat_fuzz::kLargestAllocation ? std::malloc(bytes ? bytes : 1) : nullptr;
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, size_t) noexcept {
  std::free(p);
}
