// Interval warps: the [0,1) samplers from 32 and 64 bits, their first-preimage
// inverses, the lerps, and the exact sampler of every float of [a,b).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "sampling/interval.h"
#include "sampling/pcg32.h"
#include "sampling/unit_float.h"

namespace warpcheck {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A random source that counts its draws.
struct CountingRng {
    Pcg32 pcg{7, 11};
    uint64_t calls = 0;
    uint64_t operator()() {
        ++calls;
        return pcg.next_u64();
    }
};

// The first word given, then a PCG stream.
struct FirstThen {
    uint64_t first;
    Pcg32 rest{3, 5};
    uint64_t calls = 0;
    uint64_t operator()() { return calls++ == 0 ? first : rest.next_u64(); }
};

// --- [0,1) from 32 bits -------------------------------------------------------

TEST(UnitFloat32, MultiplyKnownValues) {
    EXPECT_EQ(UnitFloatMul{}.sample(0), 0.0f);
    EXPECT_EQ(UnitFloatMul{}.sample(1), 0x1p-32f);
    EXPECT_EQ(UnitFloatMul{}.sample(0x80000000u), 0.5f);
    // The 128 largest inputs round to 1; the one below does not.
    EXPECT_EQ(UnitFloatMul{}.sample(0xffffffffu), 1.0f);
    EXPECT_EQ(UnitFloatMul{}.sample(0xffffffffu - 127), 1.0f);
    EXPECT_EQ(UnitFloatMul{}.sample(0xffffffffu - 128), kOneMinusEpsilon);
    EXPECT_EQ(UnitFloatMulClamped{}.sample(0xffffffffu), kOneMinusEpsilon);
    EXPECT_EQ(UnitFloatMulClamped{}.sample(0x80000000u), 0.5f);
}

TEST(UnitFloat32, GridSamplersKnownValues) {
    EXPECT_EQ(UnitFloat24Bit{}.sample(0xffffffffu), 1.0f - 0x1p-24f);
    EXPECT_EQ(UnitFloat24Bit{}.sample(0x000000ffu), 0.0f);
    EXPECT_EQ(UnitFloat24Bit{}.sample(0x00000100u), 0x1p-24f);
    EXPECT_EQ(UnitFloatBits{}.sample(0xffffffffu), 1.0f - 0x1p-23f);
    EXPECT_EQ(UnitFloatBits{}.sample(0x000001ffu), 0.0f);
    EXPECT_EQ(UnitFloatBits{}.sample(0x00000200u), 0x1p-23f);
    EXPECT_EQ(UnitFloatBits{}.sample(0x80000000u), 0.5f);
}

template <typename Sample, typename Invert>
void expect_first_preimages(Sample sample, Invert invert) {
    Pcg32 rng(1, 2);
    std::vector<uint32_t> inputs = {0, 1, 2, 255, 256, 0x00ffffffu, 0x01000000u, 0x7fffffffu, 0x80000000u,
                                    0xffffff7fu, 0xffffff80u, 0xfffffffeu, 0xffffffffu};
    for (int i = 0; i < 200000; ++i) inputs.push_back(rng.next_u32());
    for (uint32_t u : inputs) {
        const float x = sample(u);
        const uint32_t first = invert(x);
        ASSERT_EQ(sample(first), x) << "u = " << u;
        ASSERT_LE(first, u);
        if (first > 0) {
            ASSERT_LT(sample(first - 1), x) << "u = " << u;  // the first one
        }
    }
}

TEST(UnitFloat32, InversesReturnTheFirstPreimage) {
    expect_first_preimages([](uint32_t u) { return UnitFloatMul{}.sample(u); },
                           [](float x) { return UnitFloatMul{}.invert(x); });
    expect_first_preimages([](uint32_t u) { return UnitFloatMulClamped{}.sample(u); },
                           [](float x) { return UnitFloatMulClamped{}.invert(x); });
    expect_first_preimages([](uint32_t u) { return UnitFloat24Bit{}.sample(u); },
                           [](float x) { return UnitFloat24Bit{}.invert(x); });
    expect_first_preimages([](uint32_t u) { return UnitFloatBits{}.sample(u); },
                           [](float x) { return UnitFloatBits{}.invert(x); });
}

TEST(UnitFloat32, InversesAreTheCdfBetweenOutputs) {
    // A float that is never produced maps to the first input above it.
    const float unreachable = 0x1.000002p-30f;  // 2^-30 (1 + 2^-23): below 2^-8 only multiples of 2^-32 appear
    EXPECT_EQ(UnitFloatMul{}.invert(unreachable), 5u);
    EXPECT_EQ(UnitFloatMul{}.invert(-1.0f), 0u);
    EXPECT_EQ(UnitFloatMul{}.invert(kNaN), 0u);
    EXPECT_EQ(UnitFloatMul{}.invert(2.0f), 0xffffffffu);
    EXPECT_EQ(UnitFloat24Bit{}.invert(0x1.8p-30f), 1u << 8);  // off the 2^-24 grid: the next grid point
    EXPECT_EQ(UnitFloatBits{}.invert(0x1.8p-30f), 1u << 9);
}

// --- [0,1) from 64 bits ------------------------------------------------------

TEST(UnitFloat64, ReynoldsKnownValuesAndFirstPreimages) {
    EXPECT_EQ(UnitFloatReynolds{}.sample(uint64_t{1} << 63), 0.5f);
    EXPECT_EQ(UnitFloatReynolds{}.sample(~uint64_t{0}), kOneMinusEpsilon);
    EXPECT_EQ(UnitFloatReynolds{}.sample(uint64_t{1} << 23), 0x1p-41f);  // one leading one at the bottom
    EXPECT_EQ(UnitFloatReynolds{}.sample(0), 0.0f);
    EXPECT_EQ(UnitFloatReynolds{}.sample(5), 5 * 0x1p-64f);
    Pcg32 rng(4, 4);
    for (int i = 0; i < 200000; ++i) {
        const uint64_t bits = rng.next_u64() >> (i % 64);
        const float x = UnitFloatReynolds{}.sample(bits);
        ASSERT_LT(x, 1.0f);
        ASSERT_GE(x, 0.0f);
        const uint64_t first = UnitFloatReynolds{}.invert(x);
        ASSERT_EQ(UnitFloatReynolds{}.sample(first), x);
        ASSERT_LE(first, bits);
    }
}

TEST(UnitFloat64, WalkerReachesTheDenormalsAndTerminates) {
    // All-zero words: the count runs down to the denormals and stops there.
    uint64_t calls = 0;
    auto zeros = [&calls]() -> uint64_t {
        ++calls;
        return 0;
    };
    EXPECT_EQ(UnitFloatWalker{}.sample(zeros), 0.0f);
    EXPECT_LE(calls, 7u);
    // First word 5, then zeros: a denormal with significand 5.
    calls = 0;
    auto five_then_zeros = [&calls]() -> uint64_t { return calls++ == 0 ? 5 : 0; };
    EXPECT_EQ(UnitFloatWalker{}.sample(five_then_zeros), 5 * 0x1p-149f);
    // First word 5, then a word with one leading zero: exponent -1 - 41 - 1.
    calls = 0;
    auto five_then_half = [&calls]() -> uint64_t { return calls++ == 0 ? 5 : uint64_t{1} << 62; };
    EXPECT_EQ(UnitFloatWalker{}.sample(five_then_half), bits_to_float((127u - 43u) << 23 | 5u));
}

TEST(UnitFloat64, WalkerUsesOneWordAndInvertsIt) {
    CountingRng rng;
    for (int i = 0; i < 100000; ++i) {
        const uint64_t before = rng.calls;
        const float x = UnitFloatWalker{}.sample(rng);
        ASSERT_EQ(rng.calls, before + 1);
        ASSERT_GE(x, 0.0f);
        ASSERT_LT(x, 1.0f);
    }
    Pcg32 pcg(9, 9);
    for (int i = 0; i < 100000; ++i) {
        const uint64_t w = pcg.next_u64() >> (i % 40);
        FirstThen src{w};
        const float x = UnitFloatWalker{}.sample(src);
        FirstThen again{UnitFloatWalker{}.invert(x)};
        ASSERT_EQ(UnitFloatWalker{}.sample(again), x);
        ASSERT_LE(UnitFloatWalker{}.invert(x), w);
    }
    EXPECT_EQ(UnitFloatWalker{}.invert(0.5f), uint64_t{1} << 63);
    EXPECT_EQ(UnitFloatWalker{}.invert(0.75f), uint64_t{3} << 62);
}

TEST(UnitFloat64, RandomSourcesOf32BitsAreCalledTwicePerWord) {
    Pcg32 a(2, 3), b(2, 3);
    int calls = 0;
    auto u32 = [&a, &calls]() -> uint32_t {
        ++calls;
        return a.next_u32();
    };
    auto u64 = [&b]() -> uint64_t { return b.next_u64(); };  // high half first, as the 32-bit pairs
    for (int i = 0; i < 1000; ++i) ASSERT_EQ(UnitFloatWalker{}.sample(u32), UnitFloatWalker{}.sample(u64));
    EXPECT_EQ(calls, 2000);
    const UniformFloatInterval interval(-3.0f, 5.0f);
    for (int i = 0; i < 1000; ++i) ASSERT_EQ(interval.sample(u32), interval.sample(u64));
}

TEST(UnitFloat64, WalkerBinadeMassesAreHalves) {
    CountingRng rng;
    constexpr int n = 1 << 20;
    int top = 0, second = 0;
    for (int i = 0; i < n; ++i) {
        const float x = UnitFloatWalker{}.sample(rng);
        top += x >= 0.5f;
        second += x >= 0.25f && x < 0.5f;
    }
    // 5 standard deviations.
    EXPECT_NEAR(top, n / 2, 5 * std::sqrt(n * 0.25));
    EXPECT_NEAR(second, n / 4, 5 * std::sqrt(n * 0.1875));
}

// --- lerps ---------------------------------------------------------------------

TEST(LerpInterval, ValidatesItsParameters) {
    EXPECT_THROW(LerpInterval(1.0f, 1.0f, LerpInterval::Form::Offset), std::invalid_argument);
    EXPECT_THROW(LerpInterval(2.0f, 1.0f, LerpInterval::Form::Offset), std::invalid_argument);
    EXPECT_THROW(LerpInterval(kNaN, 1.0f, LerpInterval::Form::Blend), std::invalid_argument);
    EXPECT_THROW(LerpInterval(0.0f, kInf, LerpInterval::Form::Blend), std::invalid_argument);
    EXPECT_THROW(LerpInterval(-3e38f, 3e38f, LerpInterval::Form::Offset), std::invalid_argument);  // b - a overflows
}

TEST(LerpInterval, TheKnownFailures) {
    // a + t (b - a) reaches b below t = 1 on [1, 3).
    EXPECT_EQ(lerp_offset(1.0f - 0x1p-24f, 1.0f, 3.0f), 3.0f);
    // (1 - t) a + t b is exact at both ends...
    EXPECT_EQ(lerp_blend(0.0f, 0.2f, 0.3f), 0.2f);
    EXPECT_EQ(lerp_blend(1.0f, 0.2f, 0.3f), 0.3f);
    const LerpInterval lerp(-3.0f, 5.0f, LerpInterval::Form::Offset);
    EXPECT_EQ(lerp.sample(0.5f), 1.0f);
    EXPECT_EQ(lerp.invert(1.0f), 0.5f);
    EXPECT_EQ(lerp.pdf(0.0f), 0.125f);
    EXPECT_EQ(lerp.pdf(6.0f), 0.0f);
}

// --- every float of [a,b) ---------------------------------------------------------

TEST(UniformFloatInterval, ValidatesItsParameters) {
    EXPECT_THROW(UniformFloatInterval(1.0f, 0.0f), std::invalid_argument);
    EXPECT_THROW(UniformFloatInterval(1.0f, 1.0f), std::invalid_argument);
    EXPECT_THROW(UniformFloatInterval(kNaN, 1.0f), std::invalid_argument);
    EXPECT_THROW(UniformFloatInterval(0.0f, kInf), std::invalid_argument);
    EXPECT_THROW(UniformFloatInterval(-kInf, 0.0f, true), std::invalid_argument);
    EXPECT_NO_THROW(UniformFloatInterval(1.0f, 1.0f, true));  // [a,a] is a point
    CountingRng rng;
    EXPECT_EQ(UniformFloatInterval(2.0f, 2.0f, true).sample(rng), 2.0f);
}

struct IntervalCase {
    float a, b;
};

TEST(UniformFloatInterval, StaysInsideAndInvertsEveryFirstWord) {
    const IntervalCase cases[] = {{0.0f, 1.0f},       {-1.0f, 1.0f},        {1.0f, 1.0000001f}, {0.999f, 1.001f},
                                  {-3.0f, 5.0f},      {-1e-30f, 1.0f},      {-1.0f, -0.5f},     {-1e-40f, 1e-40f},
                                  {1e-30f, 1e30f},    {-1e30f, -1e-30f},    {-0.0f, 1.0f},      {-1.0f, 0.0f},
                                  {0.0f, 0x1p-140f},  {-3e38f, 3e38f},      {5.0f, 5.000001f}};
    Pcg32 pcg(5, 6);
    for (const auto& c : cases) {
        const UniformFloatInterval interval(c.a, c.b);
        const float reach = 0x1p-38f * std::max(std::fabs(c.a), std::fabs(c.b));
        for (int i = 0; i < 20000; ++i) {
            uint64_t w = pcg.next_u64();
            if (i < 8) w = ~uint64_t{0} - static_cast<uint64_t>(i);
            if (i >= 8 && i < 16) w = static_cast<uint64_t>(i - 8);
            FirstThen src{w};
            const float x = interval.sample(src);
            ASSERT_GE(x, c.a) << c.a << " " << c.b;
            ASSERT_LT(x, c.b) << c.a << " " << c.b;
            if (!(std::fabs(x) >= reach || interval.narrow())) continue;  // further words decide there
            const uint64_t first = interval.invert(x);
            FirstThen again{first};
            ASSERT_EQ(interval.sample(again), x) << c.a << " " << c.b << " w = " << w;
            if (src.calls == 1) {
                ASSERT_LE(first, w);  // accepted at once: the first preimage
            }
        }
    }
}

TEST(UniformFloatInterval, NarrowIntervalsCostOneDraw) {
    // Within one binade, straddling a binade, and at the denormals: the direct path.
    for (const auto& c : {IntervalCase{1.0f, 1.0f + 0x1p-20f}, IntervalCase{1.0f - 0x1p-20f, 1.0f + 0x1p-20f},
                          IntervalCase{0.999f, 1.001f}, IntervalCase{-0x1p-130f, 0x1p-130f},
                          IntervalCase{1e20f, 1.0000001e20f}}) {
        const UniformFloatInterval interval(c.a, c.b);
        EXPECT_TRUE(interval.narrow()) << c.a << " " << c.b;
        CountingRng rng;
        constexpr int n = 100000;
        for (int i = 0; i < n; ++i) interval.sample(rng);
        EXPECT_LE(rng.calls, n + 2u) << c.a << " " << c.b;  // rejection below 2^-24 per draw
    }
}

TEST(UniformFloatInterval, WideIntervalsCostFewDraws) {
    for (const auto& c : {IntervalCase{0.0f, 1.0f}, IntervalCase{1e-30f, 1e30f}, IntervalCase{-3.0f, 5.0f},
                          IntervalCase{-1e-30f, 1.0f}}) {
        const UniformFloatInterval interval(c.a, c.b);
        EXPECT_FALSE(interval.narrow());
        CountingRng rng;
        constexpr int n = 100000;
        for (int i = 0; i < n; ++i) interval.sample(rng);
        EXPECT_LE(rng.calls, 2.2 * n) << c.a << " " << c.b;  // acceptance >= 1/2 for these
    }
}

TEST(UniformFloatInterval, RejectionIsBoundedWithADefinedFallback) {
    // A source stuck on the top word, which every path rejects: the loop ends
    // after kMaxAttempts draws and returns a.
    uint64_t calls = 0;
    auto stuck = [&calls]() -> uint64_t {
        ++calls;
        return ~uint64_t{0};
    };
    const UniformFloatInterval narrow(1.0f, 1.0f + 3 * 0x1p-23f);  // N = 3: the top words reject
    EXPECT_EQ(narrow.sample(stuck), 1.0f);
    EXPECT_EQ(calls, static_cast<uint64_t>(UniformFloatInterval::kMaxAttempts));
    calls = 0;
    const UniformFloatInterval wide(0.0f, 0.75f);
    EXPECT_EQ(wide.sample(stuck), 0.0f);
    EXPECT_LE(calls, 6u * UniformFloatInterval::kMaxAttempts);
}

double fraction(const UniformFloatInterval& interval, int n, bool (*in)(float)) {
    CountingRng rng;
    int hits = 0;
    for (int i = 0; i < n; ++i) hits += in(interval.sample(rng));
    return static_cast<double>(hits) / n;
}

TEST(UniformFloatInterval, MassesAreProportionalToLength) {
    constexpr int n = 1 << 20;
    const double sigma5 = 5.0 * 0.5 / std::sqrt(static_cast<double>(n));
    // Straddling a binade: [0.75, 1.5), below 1 a third of the length.
    EXPECT_NEAR(fraction(UniformFloatInterval(0.75f, 1.5f), n, [](float x) { return x < 1.0f; }), 1.0 / 3.0, sigma5);
    // Spanning zero: [-3, 5), negative 3/8.
    EXPECT_NEAR(fraction(UniformFloatInterval(-3.0f, 5.0f), n, [](float x) { return x < 0.0f; }), 3.0 / 8.0, sigma5);
    // Negative side near zero: [-1, 0) has [-2^-10, 0) with 2^-10.
    EXPECT_NEAR(fraction(UniformFloatInterval(-1.0f, 0.0f), n, [](float x) { return x >= -0x1p-10f; }), 0x1p-10,
                5.0 * std::sqrt(0x1p-10 / n));
    // Narrow, three floats of equal spacing: each a third.
    EXPECT_NEAR(fraction(UniformFloatInterval(1.0f, 1.0f + 3 * 0x1p-23f), n, [](float x) { return x == 1.0f; }),
                1.0 / 3.0, sigma5);
    // Narrow across a binade: [1 - 2^-24, 1 + 2^-23): 1 - 2^-24 has a third of the length.
    EXPECT_NEAR(fraction(UniformFloatInterval(kOneMinusEpsilon, 1.0f + 0x1p-23f), n,
                         [](float x) { return x == kOneMinusEpsilon; }),
                1.0 / 3.0, sigma5);
    // Closed [1, next(1)]: both ends get half a spacing.
    EXPECT_NEAR(fraction(UniformFloatInterval(1.0f, 1.0f + 0x1p-23f, true), n, [](float x) { return x == 1.0f; }), 0.5,
                sigma5);
}

TEST(UniformFloatInterval, ClosedIntervalsReachB) {
    const UniformFloatInterval closed(0.0f, 1.0f, true);
    CountingRng rng;
    for (int i = 0; i < 100000; ++i) {
        const float x = closed.sample(rng);
        ASSERT_GE(x, 0.0f);
        ASSERT_LE(x, 1.0f);
    }
    EXPECT_EQ(closed.pdf(1.0f), 1.0f);
    EXPECT_EQ(UniformFloatInterval(0.0f, 1.0f).pdf(1.0f), 0.0f);
    EXPECT_EQ(UniformFloatInterval(-3.0f, 5.0f).cdf(1.0f), 0.5);
}

}  // namespace
}  // namespace warpcheck
