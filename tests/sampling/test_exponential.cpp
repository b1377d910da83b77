// Exponential and trimmed exponential warps: parameters, known values,
// normalisation, round trips at the edges, and the measured accuracy near u = 0.
//
// The accuracy sweeps run over every k-th float of [0, 2^-20] (k = 127 by
// default, 7M inputs) and over every k-th float of [2^-20, 1). Setting
// WARPCHECK_FULL_SWEEP=1 makes k = 1: every float (about 1.07e9 inputs, a
// minute or two). The measured figures are printed as test properties.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>

#include "sampling/exponential.h"
#include "sampling/float_bits.h"

namespace warpcheck {
namespace {

const float kExponentialEdges[] = {0.0f, 0x1p-149f, 0x1p-126f, 0x1p-25f, 0x1p-24f, 0.5f, kOneMinusEpsilon};

uint32_t sweep_stride() {
    const char* full = std::getenv("WARPCHECK_FULL_SWEEP");
    return full != nullptr && std::string(full) == "1" ? 1u : 127u;
}

/// Error of a float result against a long double reference, in units of the
/// float spacing at the reference (ulps). Results below FLT_MIN are measured in
/// the denormal spacing 2^-149 instead, where no float does better.
double ulp_error(float got, long double ref) {
    const long double spacing =
        std::fabs(ref) < std::numeric_limits<float>::min()
            ? 0x1p-149L
            : std::ldexp(1.0L, std::ilogb(static_cast<float>(ref)) - kFloatSignificandBits);
    return static_cast<double>(std::fabs(static_cast<long double>(got) - ref) / spacing);
}

struct SweepResult {
    double max_ulps = 0.0;
    float worst_u = 0.0f;
    uint64_t count = 0;
};

template <typename Warp, typename Reference>
SweepResult sweep(const Warp& warp, Reference ref, float lo, float hi, uint32_t stride) {
    SweepResult r;
    for (uint32_t bits = float_to_bits(lo); bits < float_to_bits(hi); bits += stride) {
        const float u = bits_to_float(bits);
        const double e = ulp_error(warp.sample(u), ref(static_cast<long double>(u)));
        ++r.count;
        if (!(e <= r.max_ulps)) {
            r.max_ulps = e;
            r.worst_u = u;
        }
    }
    return r;
}

// ---------------------------------------------------------------------------

TEST(Exponential, RejectsBadRates) {
    for (float a : {0.0f, -1.0f, 1e-38f, std::numeric_limits<float>::infinity(), std::nanf("")})
        EXPECT_THROW(Exponential{a}, std::invalid_argument) << a;
    EXPECT_NO_THROW(Exponential{Exponential::kMinRate});
}

TEST(Exponential, KnownValues) {
    const Exponential e(2.0f);
    EXPECT_EQ(e.sample(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(e.sample(0.5f), std::log(2.0f) / 2.0f);
    EXPECT_FLOAT_EQ(e.pdf(0.0f), 2.0f);
    EXPECT_EQ(e.pdf(-1.0f), 0.0f);
    EXPECT_FLOAT_EQ(e.invert(std::log(2.0f) / 2.0f), 0.5f);
    // u >= 1 is clamped: every sample is finite, even at the smallest rate.
    EXPECT_TRUE(std::isfinite(Exponential(Exponential::kMinRate).sample(1.0f)));
}

TEST(Exponential, RoundTripAtEdges) {
    for (float a : {0.1f, 1.0f, 10.0f, 1e-30f, 1e30f}) {
        const Exponential e(a);
        for (float u : kExponentialEdges) {
            const float back = e.invert(e.sample(u));
            EXPECT_LE(std::abs(back - u), 1e-6f * std::max(u, 1e-30f) + 0x1p-24f) << "a=" << a << " u=" << u;
        }
    }
}

TEST(Exponential, NaiveFormulaLosesSmallInputs) {
    // Why log1p: -log(1 - u) is 0 for every float u below 2^-25 (1 - u rounds to 1).
    const float u = 0x1p-26f;
    EXPECT_EQ(-std::log(1.0f - u), 0.0f);
    EXPECT_GT(Exponential(1.0f).sample(u), 0.0f);
}

TEST(Exponential, AccuracyNearZero) {
    const uint32_t stride = sweep_stride();
    for (float a : {0.1f, 1.0f, 10.0f}) {
        const Exponential e(a);
        auto ref = [a](long double u) { return -std::log1p(-u) / static_cast<long double>(a); };
        const SweepResult lo = sweep(e, ref, 0.0f, 0x1p-20f, stride);
        const SweepResult hi = sweep(e, ref, 0x1p-20f, 1.0f, stride);
        RecordProperty("exp_a" + std::to_string(a) + "_max_ulps_below_2^-20", std::to_string(lo.max_ulps));
        RecordProperty("exp_a" + std::to_string(a) + "_max_ulps_above_2^-20", std::to_string(hi.max_ulps));
        std::printf("exponential a=%g: max error %.2f ulp on [0, 2^-20] (%llu inputs, worst u=%a), "
                    "%.2f ulp on [2^-20, 1) (worst u=%a)\n",
                    a, lo.max_ulps, static_cast<unsigned long long>(lo.count), lo.worst_u, hi.max_ulps, hi.worst_u);
        EXPECT_LE(lo.max_ulps, 2.0) << "a=" << a << " worst u=" << lo.worst_u;
        EXPECT_LE(hi.max_ulps, 2.0) << "a=" << a << " worst u=" << hi.worst_u;
    }
}

// ---------------------------------------------------------------------------

TEST(TrimmedExponential, RejectsBadParameters) {
    EXPECT_THROW(TrimmedExponential(-1.0f, 1.0f), std::invalid_argument);
    EXPECT_THROW(TrimmedExponential(std::nanf(""), 1.0f), std::invalid_argument);
    EXPECT_THROW(TrimmedExponential(1.0f, 0.0f), std::invalid_argument);
    EXPECT_THROW(TrimmedExponential(1.0f, std::numeric_limits<float>::infinity()), std::invalid_argument);
    EXPECT_THROW(TrimmedExponential(1e30f, 1e30f), std::invalid_argument);   // c xmax overflows
    EXPECT_THROW(TrimmedExponential(0.0f, 1e-45f), std::invalid_argument);   // density 1/xmax overflows
    EXPECT_NO_THROW(TrimmedExponential(0.0f, 1.0f));
}

TEST(TrimmedExponential, ZeroRateIsUniform) {
    const TrimmedExponential t(0.0f, 3.0f);
    for (float u : kExponentialEdges) EXPECT_EQ(t.sample(u), u * 3.0f);
    EXPECT_FLOAT_EQ(t.pdf(1.0f), 1.0f / 3.0f);
    EXPECT_FLOAT_EQ(t.invert(1.5f), 0.5f);
}

TEST(TrimmedExponential, LargeRateMatchesUntrimmed) {
    // exp(-100) is far below float precision: the trimmed distribution is the plain one.
    const TrimmedExponential t(100.0f, 1.0f);
    const Exponential e(100.0f);
    for (float u : {0x1p-24f, 0.1f, 0.5f, 0.9f, kOneMinusEpsilon}) {
        EXPECT_FLOAT_EQ(t.sample(u), e.sample(u));
        EXPECT_FLOAT_EQ(t.pdf(t.sample(u)), e.pdf(e.sample(u)));
    }
}

TEST(TrimmedExponential, DensityIntegratesToOne) {
    for (auto [c, xmax] : {std::pair{1e-6f, 1.0f}, {1.0f, 1.0f}, {1.0f, 4.0f}, {30.0f, 2.0f}, {0.0f, 5.0f}}) {
        const TrimmedExponential t(c, xmax);
        // Composite Simpson on 20000 panels: the error is below 1e-9 for these rates.
        const int n = 20000;
        const double h = static_cast<double>(xmax) / n;
        double sum = 0.0;
        for (int i = 0; i <= n; ++i) {
            const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
            sum += w * t.pdf(static_cast<float>(std::min(i * h, static_cast<double>(xmax))));
        }
        const double integral = sum * h / 3.0;
        EXPECT_LE(std::abs(integral - 1.0), 1e-5) << "c=" << c << " xmax=" << xmax;
    }
}

TEST(TrimmedExponential, RoundTripAtEdges) {
    for (auto [c, xmax] : {std::pair{1e-6f, 1.0f}, {1.0f, 1.0f}, {100.0f, 1.0f}, {0.0f, 2.0f}, {1e-30f, 1e10f}}) {
        const TrimmedExponential t(c, xmax);
        for (float u : kExponentialEdges) {
            const float x = t.sample(u);
            EXPECT_GE(x, 0.0f);
            EXPECT_LE(x, xmax);
            EXPECT_LE(std::abs(t.invert(x) - u), 4e-7f * std::max(u, 1e-30f) + 0x1p-24f) << c << " " << u;
        }
    }
}

TEST(TrimmedExponential, AccuracyNearZero) {
    const uint32_t stride = sweep_stride();
    for (auto [c, xmax] : {std::pair{1e-6f, 1.0f}, {1.0f, 1.0f}, {100.0f, 1.0f}, {1e-30f, 1.0f}}) {
        const TrimmedExponential t(c, xmax);
        auto ref = [c = static_cast<long double>(c), xmax = static_cast<long double>(xmax)](long double u) {
            return -std::log1p(u * std::expm1(-c * xmax)) / c;
        };
        const SweepResult lo = sweep(t, ref, 0.0f, 0x1p-20f, stride);
        const SweepResult hi = sweep(t, ref, 0x1p-20f, 1.0f, stride);
        std::printf("trimmed exponential c=%g xmax=%g: max error %.2f ulp on [0, 2^-20] (worst u=%a), "
                    "%.2f ulp on [2^-20, 1) (worst u=%a)\n",
                    c, xmax, lo.max_ulps, lo.worst_u, hi.max_ulps, hi.worst_u);
        EXPECT_LE(lo.max_ulps, 4.0) << "c=" << c << " worst u=" << lo.worst_u;
        EXPECT_LE(hi.max_ulps, 4.0) << "c=" << c << " worst u=" << hi.worst_u;
    }
}

}  // namespace
}  // namespace warpcheck
