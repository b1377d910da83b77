// Correction of the significance level when one run makes many tests.
#pragma once

#include <cmath>

namespace warpcheck::chi2 {

/// Šidák's per-test level: with m independent tests each at level
/// 1 - (1 - alpha)^(1/m), the chance that any of them rejects a true null
/// hypothesis is exactly alpha. Computed as -expm1(log1p(-alpha) / m), which
/// keeps full precision for small alpha and large m. m < 1 gives alpha; alpha
/// outside [0, 1] gives NaN (and a NaN level fails every test that uses it).
inline double sidak_level(double alpha, int m) {
    if (!(alpha >= 0.0 && alpha <= 1.0)) return std::nan("");
    if (m <= 1) return alpha;
    return -std::expm1(std::log1p(-alpha) / m);
}

}  // namespace warpcheck::chi2
