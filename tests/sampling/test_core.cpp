// Float bit helpers, PCG32 and hashing: the ground every other result stands on.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <vector>

#include "sampling/float_bits.h"
#include "sampling/hash.h"
#include "sampling/pcg32.h"

namespace warpcheck {
namespace {

TEST(FloatBits, FieldsOfKnownFloats) {
    EXPECT_EQ(float_to_bits(1.0f), 0x3f800000u);
    EXPECT_EQ(bits_to_float(0x3f000000u), 0.5f);
    EXPECT_EQ(float_exponent(1.0f), 0);
    EXPECT_EQ(float_exponent(0.75f), -1);
    EXPECT_EQ(float_significand(0.75f), 0x400000u);
    EXPECT_EQ(float_sign_bit(-2.0f), 1u);
    EXPECT_EQ(float_sign_bit(-0.0f), 1u);
    EXPECT_EQ(float_sign_bit(3.0f), 0u);
    EXPECT_EQ(float_biased_exponent(std::numeric_limits<float>::denorm_min()), 0);
    EXPECT_EQ(kOneMinusEpsilon, 1.0f - 0x1p-24f);
}

TEST(FloatBits, NextFloatStepsOneUlp) {
    EXPECT_EQ(next_float_up(1.0f), 1.0f + 0x1p-23f);
    EXPECT_EQ(next_float_down(1.0f), kOneMinusEpsilon);
    EXPECT_EQ(next_float_up(0.0f), std::numeric_limits<float>::denorm_min());
    EXPECT_EQ(next_float_up(-0.0f), std::numeric_limits<float>::denorm_min());
    EXPECT_EQ(next_float_down(0.0f), -std::numeric_limits<float>::denorm_min());
    EXPECT_EQ(next_float_up(-1.0f), -kOneMinusEpsilon);
    EXPECT_EQ(next_float_up(std::numeric_limits<float>::max()), std::numeric_limits<float>::infinity());
    EXPECT_EQ(next_float_up(std::numeric_limits<float>::infinity()), std::numeric_limits<float>::infinity());
    EXPECT_TRUE(std::isnan(next_float_up(std::numeric_limits<float>::quiet_NaN())));
    EXPECT_EQ(next_float_down(next_float_up(0.3f)), 0.3f);
}

TEST(FloatBits, CountLeadingZeros) {
    EXPECT_EQ(count_leading_zeros(uint32_t{0}), 32);
    EXPECT_EQ(count_leading_zeros(uint32_t{1}), 31);
    EXPECT_EQ(count_leading_zeros(uint32_t{0x80000000u}), 0);
    EXPECT_EQ(count_leading_zeros(uint64_t{1}), 63);
    EXPECT_EQ(count_leading_zeros(uint64_t{0}), 64);
}

// Reference output of the PCG32 demo program (pcg32-demo from the PCG basic C
// library) for initial state 42 and sequence 54.
TEST(Pcg32, MatchesReferenceStream) {
    Pcg32 rng(54u, 42u);
    const uint32_t expected[] = {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u, 0x83d2f293u, 0xbfa4784bu, 0xcbed606eu};
    for (uint32_t e : expected) EXPECT_EQ(rng.next_u32(), e);
}

TEST(Pcg32, AdvanceJumpsForwardAndBack) {
    Pcg32 a(7, 1234), b(7, 1234);
    for (int i = 0; i < 1000; ++i) a.next_u32();
    b.advance(1000);
    EXPECT_EQ(a, b);
    EXPECT_EQ(a.next_u32(), b.next_u32());
    b.advance(-1001);
    Pcg32 c(7, 1234);
    EXPECT_EQ(b, c);
    Pcg32 d(7, 1234);
    d.advance(0);
    EXPECT_EQ(d, c);
}

// next_u64s computes eight steps from one state: the draws and the state after
// must be next_u64's, for every length (the tail after the blocks of four
// draws included) and every stream.
TEST(Pcg32, BlockDrawsAreTheDrawsOneByOne) {
    for (uint64_t stream : {0ull, 1ull, 54ull, 0x7fffffffffffffffull})
        for (std::size_t n : {0, 1, 2, 3, 4, 5, 7, 8, 9, 31, 768, 1001}) {
            Pcg32 one(stream, 42 + n), block(stream, 42 + n);
            std::vector<uint64_t> expected(n), got(n + 1, 0xdeadbeefull);
            for (auto& e : expected) e = one.next_u64();
            block.next_u64s(got.data(), n);
            for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(got[i], expected[i]) << "stream " << stream << ", draw " << i;
            EXPECT_EQ(got[n], 0xdeadbeefull) << "wrote past the end";
            EXPECT_EQ(block, one) << "stream " << stream << ", " << n << " draws";
        }
}

TEST(Pcg32, StreamsDiffer) {
    Pcg32 a(1, 99), b(2, 99);
    int same = 0;
    for (int i = 0; i < 64; ++i) same += a.next_u32() == b.next_u32();
    EXPECT_LT(same, 2);
}

TEST(Pcg32, FloatsStayBelowOneOnTheGrid) {
    Pcg32 rng(3, 3);
    for (int i = 0; i < 100000; ++i) {
        const float u = rng.next_float();
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
        ASSERT_EQ(u * 0x1p24f, std::floor(u * 0x1p24f));  // on the 2^-24 grid
    }
    const double d = rng.next_double();
    EXPECT_TRUE(d >= 0.0 && d < 1.0);
}

TEST(Hash, StableAndSensitive) {
    // Pinned: streams, and so every statistic warpcheck prints, depend on these
    // values. A change here changes every published figure of a seed.
    EXPECT_EQ(hash_string(""), mix64(0xcbf29ce484222325ULL));
    EXPECT_EQ(hash_string("a"), mix64((0xcbf29ce484222325ULL ^ 'a') * 0x100000001b3ULL));
    std::set<uint64_t> seen;
    for (const char* name : {"uniform_hemisphere/chi2", "uniform_hemisphere/roundtrip", "uniform_sphere/chi2", "a", "b"})
        seen.insert(hash_string(name));
    EXPECT_EQ(seen.size(), 5u);
    const StreamId s1 = stream_for("x", 1), s2 = stream_for("x", 2), s3 = stream_for("x", 1);
    EXPECT_NE(s1.sequence, s2.sequence);
    EXPECT_EQ(s1.sequence, s3.sequence);
    EXPECT_EQ(s1.seed, s3.seed);
    EXPECT_NE(hash_values(1, 2), hash_values(2, 1));
}

}  // namespace
}  // namespace warpcheck
