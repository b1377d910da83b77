#include <cmath>

#include <gtest/gtest.h>

#include "chi2/multiple_testing.h"

namespace warpcheck::chi2 {
namespace {

TEST(SidakLevel, OneTestKeepsAlpha) { EXPECT_EQ(sidak_level(0.01, 1), 0.01); }

TEST(SidakLevel, FamilyWiseLevelIsExactlyAlpha) {
    for (int m : {2, 10, 37, 1000, 100000}) {
        const double level = sidak_level(0.01, m);
        // m independent tests at `level`: P(no rejection) = (1 - level)^m = 1 - alpha.
        EXPECT_NEAR(-std::expm1(m * std::log1p(-level)), 0.01, 1e-15) << m;
        // Šidák is slightly less strict than Bonferroni and stricter than alpha.
        EXPECT_GE(level, 0.01 / m) << m;
        EXPECT_LT(level, 0.01) << m;
    }
}

TEST(SidakLevel, KnownValue) {
    // 1 - 0.99^(1/100) with Python's decimal module at 40 digits:
    // 1 - exp(ln(0.99) / 100) = 0.0001004983082416679...
    EXPECT_NEAR(sidak_level(0.01, 100), 1.004983082416679e-4, 1e-18);
}

TEST(SidakLevel, InvalidAlphaIsNaNAndNaNFailsEveryTest) {
    const double level = sidak_level(std::nan(""), 5);
    EXPECT_TRUE(std::isnan(level));
    EXPECT_TRUE(std::isnan(sidak_level(1.5, 5)));
    const double p = 0.5;
    EXPECT_FALSE(p >= level);  // the runner's rule: fail unless p >= level
}

}  // namespace
}  // namespace warpcheck::chi2
