// The "device" kernel of the stand-in: one built-in warp, cosine_hemisphere
// (sampling/hemisphere.h), over a buffer of inputs, as a GPU kernel would run
// it over its threads. tests/CMakeLists.txt compiles this one file several
// times, each a build a device or another compiler might make: as warpcheck
// builds it (no contraction), with -ffast-math, and with -ffast-math and fused
// multiply-adds (-mfma), the function named by WARPCHECK_KERNEL each time.
#include <cstddef>

#include "sampling/hemisphere.h"

#ifndef WARPCHECK_KERNEL
#error "compile with -DWARPCHECK_KERNEL=<function name>"
#endif

void WARPCHECK_KERNEL(const float* u, float* x, std::size_t n) {
    const warpcheck::CosineHemisphere warp;
    for (std::size_t i = 0; i < n; ++i) {
        const warpcheck::Vector3f w = warp.sample({u[2 * i], u[2 * i + 1]});
        x[3 * i] = w.x, x[3 * i + 1] = w.y, x[3 * i + 2] = w.z;
    }
}
