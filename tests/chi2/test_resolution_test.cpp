// The resolution test (chi2/resolution_test.h): uniform values of every
// resolution finer than 2^-20 pass on many seeds; values quantised to 2^-m,
// m < 20, fail at digit m + 1.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "chi2/resolution_test.h"
#include "sampling/pcg32.h"

namespace warpcheck::chi2 {
namespace {

/// n values k 2^-bits, k uniform (bits <= 32), or, with bits 0, doubles of 2^-53 resolution.
std::vector<double> uniform_values(uint64_t seed, std::size_t n, int bits) {
    Pcg32 rng(seed, 3);
    std::vector<double> u(n);
    for (double& v : u)
        v = bits == 0 ? rng.next_double() : std::ldexp(static_cast<double>(rng.next_u32() >> (32 - bits)), -bits);
    return u;
}

TEST(ResolutionTest, UniformValuesOfTwentyBitsOrMorePassOnManySeeds) {
    int below = 0, runs = 0;
    for (int bits : {20, 24, 32, 0}) {
        for (uint64_t seed = 1; seed <= 25; ++seed) {
            const ResolutionTest t = resolution_test(uniform_values(seed, 200'000, bits));
            ASSERT_EQ(t.digits, kResolutionDigits);
            EXPECT_GT(t.p_value, 1e-4) << bits << " bits, seed " << seed;
            below += t.p_value < 0.05;
            ++runs;
        }
    }
    // One p-value per run, uniform under the null: about 5 of 100 below 0.05.
    EXPECT_LE(below, 14) << "of " << runs;
}

TEST(ResolutionTest, ValuesQuantisedBelowTwentyBitsFailAtTheFirstMissingDigit) {
    for (int bits : {10, 16, 19}) {
        for (uint64_t seed = 1; seed <= 5; ++seed) {
            const ResolutionTest t = resolution_test(uniform_values(seed, 200'000, bits));
            EXPECT_LT(t.p_value, 1e-12) << bits << " bits";
            EXPECT_EQ(t.worst_digit, bits + 1);
            EXPECT_EQ(t.worst_ones_fraction, 0.0);
        }
    }
}

// A digit that is merely biased (ones 51% of the time at digit 14, about 9
// standard errors at 200,000 values) fails too.
TEST(ResolutionTest, ABiasedDigitFails) {
    std::vector<double> u = uniform_values(7, 200'000, 24);
    Pcg32 rng(11, 5);
    for (double& v : u) {
        const double bit = std::ldexp(1.0, -14);
        const bool set = std::fmod(std::floor(v / bit), 2.0) == 1.0;
        if (!set && rng.next_double() < 0.02) v += bit;  // 1% of the values move their digit 14 to 1
    }
    const ResolutionTest t = resolution_test(u);
    EXPECT_EQ(t.worst_digit, 14);
    EXPECT_LT(t.p_value, 1e-3);
}

TEST(ResolutionTest, DigitsAreCountedExactly) {
    DigitCounts c(20);
    c.add(0.0);
    c.add(0.5);                  // digit 1
    c.add(1.0 - 0x1p-24);        // all twenty digits
    c.add(0x1p-20);              // digit 20 only
    c.add(0x1p-20 - 0x1p-40);    // below 2^-20: no digit of the twenty
    EXPECT_EQ(c.n(), 5u);
    EXPECT_EQ(c.ones(1), 2u);
    for (int k = 2; k < 20; ++k) EXPECT_EQ(c.ones(k), 1u) << k;
    EXPECT_EQ(c.ones(20), 2u);
    EXPECT_THROW(c.ones(21), std::out_of_range);
    // 52 digits, in five tables: the last digit of a double's 2^-52 grid.
    DigitCounts fine(52);
    fine.add(0x1p-52);
    fine.add(0.5 + 0x1p-30);
    EXPECT_EQ(fine.ones(52), 1u);
    EXPECT_EQ(fine.ones(30), 1u);
    EXPECT_EQ(fine.ones(1), 1u);
    EXPECT_EQ(fine.ones(2), 0u);
}

TEST(ResolutionTest, MergedCountsEqualTheWhole) {
    const std::vector<double> u = uniform_values(3, 10'000, 24);
    DigitCounts whole, a, b;
    for (std::size_t i = 0; i < u.size(); ++i) {
        whole.add(u[i]);
        (i < 4000 ? a : b).add(u[i]);
    }
    a.merge(b);
    EXPECT_EQ(a.n(), whole.n());
    for (int k = 1; k <= kResolutionDigits; ++k) EXPECT_EQ(a.ones(k), whole.ones(k)) << k;
    EXPECT_EQ(resolution_test(a).p_value, resolution_test(whole).p_value);
    EXPECT_THROW(a.merge(DigitCounts(12)), std::invalid_argument);
    EXPECT_THROW(DigitCounts(0), std::invalid_argument);
    EXPECT_THROW(DigitCounts(53), std::invalid_argument);
}

TEST(ResolutionTest, TooFewValuesTestNothing) {
    const ResolutionTest t = resolution_test(std::vector<double>{0.1, 0.7, 0.3});
    EXPECT_TRUE(std::isnan(t.p_value));
    EXPECT_EQ(t.digits, 0);
}

}  // namespace
}  // namespace warpcheck::chi2
