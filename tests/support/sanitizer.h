// GEARNVH_UNDER_ASAN: defined when this translation unit is built with AddressSanitizer. GCC
// defines __SANITIZE_ADDRESS__; clang (the instrumented build's compiler) reports it only through
// __has_feature.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define GEARNVH_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define GEARNVH_UNDER_ASAN 1
#endif
#endif
