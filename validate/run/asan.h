#pragma once

// WARPCHECK_ASAN is defined where this translation unit is built with
// AddressSanitizer (GCC says so by __SANITIZE_ADDRESS__, Clang by
// __has_feature): the worker's memory limit and the huge-page re-exec are
// off there, since ASan reserves terabytes of shadow address space and
// allocates through its own allocator, which glibc's tunables do not reach.
#if defined(__SANITIZE_ADDRESS__)
#define WARPCHECK_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define WARPCHECK_ASAN 1
#endif
#endif
