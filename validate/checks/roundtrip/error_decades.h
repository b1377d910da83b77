// The round trip's error histogram (validate/checks/roundtrip/roundtrip.cpp): the bin of
// an error |invert(sample(u)) - u| by its decade, without a log10 per trip.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace warpcheck {

/// Decades of the histogram: [1e-10, 1e-9) .. [1, 10); below and above them one bin each.
inline constexpr int kErrorFirstDecade = -10;
inline constexpr int kErrorDecades = 11;

/// The histogram bin of an error > 0: floor(log10(error)) - kErrorFirstDecade + 1, clamped to
/// [0, kErrorDecades + 1], found by comparing with the powers of ten that bound the bins (a log10 per
/// trip was 7% of the check). Within 1e-12 relative of one of them, where log10's rounding (glibc:
/// within 2 ulps, 1e-15 relative) could put the decade on either side, log10 itself decides: so every
/// bin is the one floor(log10(error)) gives. A NaN or negative error falls in bin 0, as before.
inline std::size_t error_decade_bin(double error) {
    static constexpr std::array<double, kErrorDecades + 1> kPowers{1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5,
                                                                   1e-4,  1e-3, 1e-2, 1e-1, 1e0,  1e1};
    static_assert(kErrorFirstDecade == -10, "kPowers are the bins' edges");
    std::size_t bin = 0;
    for (const double power : kPowers) {
        if (std::abs(error - power) <= 1e-12 * power) {
            const int decade = static_cast<int>(std::floor(std::log10(error)));
            return static_cast<std::size_t>(std::clamp(decade - kErrorFirstDecade + 1, 0, kErrorDecades + 1));
        }
        bin += error >= power ? 1 : 0;
    }
    return bin;
}

}  // namespace warpcheck
