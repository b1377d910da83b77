// The round trip's error histogram bins by comparison with powers of ten
// (validate/checks/roundtrip/error_decades.h) must be the bins floor(log10(error)) gave:
// at every double within 300 ulps of each edge, at dyadic errors (what
// |invert(sample(u)) - u| of floats is), and at log-uniform random errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "sampling/pcg32.h"
#include "validate/checks/roundtrip/error_decades.h"

namespace warpcheck {
namespace {

std::size_t by_log10(double error) {
    const int decade = static_cast<int>(std::floor(std::log10(error)));
    return static_cast<std::size_t>(std::clamp(decade - kErrorFirstDecade + 1, 0, kErrorDecades + 1));
}

TEST(ErrorDecades, EveryDoubleNearAnEdgeIsInTheBinLog10Gives) {
    uint64_t compared = 0, below = 0, above = 0;
    for (int d = kErrorFirstDecade - 1; d <= kErrorFirstDecade + kErrorDecades + 1; ++d) {
        const double edge = std::pow(10.0, d);
        double lo = edge, hi = edge;
        for (int k = 0; k < 300; ++k) {
            lo = std::nextafter(lo, 0.0), hi = std::nextafter(hi, 1e300);
            for (const double e : {lo, hi}) {
                ASSERT_EQ(error_decade_bin(e), by_log10(e)) << "error " << e;
                ++compared;
            }
        }
        ASSERT_EQ(error_decade_bin(edge), by_log10(edge)) << "error " << edge;
        // Far enough from the edge, the bins on its two sides differ (inside the histogram's range).
        if (d > kErrorFirstDecade && d <= kErrorFirstDecade + kErrorDecades) {
            below += error_decade_bin(edge * (1 - 1e-9)) + 1 == error_decade_bin(edge * (1 + 1e-9));
            ++above;
        }
    }
    EXPECT_EQ(below, above);
    EXPECT_GT(compared, 8000u);
}

TEST(ErrorDecades, DyadicAndRandomErrorsAreInTheBinLog10Gives) {
    for (int m = 0; m < 60; ++m)
        for (uint64_t k = 1; k < 1000; ++k) {
            const double e = std::ldexp(static_cast<double>(k), -m);
            ASSERT_EQ(error_decade_bin(e), by_log10(e)) << "error " << e;
        }
    Pcg32 rng(7, 1);
    for (int i = 0; i < 1000000; ++i) {
        const double e = std::pow(10.0, -14.0 + 17.0 * rng.next_double());
        ASSERT_EQ(error_decade_bin(e), by_log10(e)) << "error " << e;
    }
    EXPECT_EQ(error_decade_bin(std::numeric_limits<double>::quiet_NaN()), 0u);
    EXPECT_EQ(error_decade_bin(1e-300), 0u);
    EXPECT_EQ(error_decade_bin(1e300), static_cast<std::size_t>(kErrorDecades + 1));
}

}  // namespace
}  // namespace warpcheck
