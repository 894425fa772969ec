#pragma once
// Whether this test binary runs under AddressSanitizer (GCC says
// __SANITIZE_ADDRESS__, clang __has_feature(address_sanitizer)).
#if defined(__SANITIZE_ADDRESS__)
#define PLEAT_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PLEAT_TEST_ASAN 1
#endif
#endif

namespace pleat_test {
#if defined(PLEAT_TEST_ASAN)
constexpr bool kUnderAddressSanitizer = true;
#else
constexpr bool kUnderAddressSanitizer = false;
#endif
}  // namespace pleat_test
