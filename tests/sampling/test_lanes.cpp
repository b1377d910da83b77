// sin_cos against the correctly rounded values, and the lane forms of
// sampling/lanes.h and sampling/lane_warps.h against their scalar twins, bit
// for bit (this file is compiled for the baseline target: the portable form;
// tests/validate/lanes/test_lane_sampling.cpp runs the AVX-512 form end to end).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

#include "sampling/disk.h"
#include "sampling/hemisphere.h"
#include "sampling/lane_warps.h"
#include "sampling/lanes.h"
#include "sampling/pcg32.h"
#include "sampling/sphere.h"
#include "sampling/trowbridge_reitz.h"

#pragma GCC diagnostic ignored "-Wpsabi"  // lane vectors between inline test helpers

namespace warpcheck {
namespace {

constexpr int W = lanes::kWidth;

bool same_bits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

TEST(SinCos, CorrectlyRoundedOnEveryTestedAngle) {
    // Every 401st float of (0, 2.01 pi] and of [-pi/4, 0) (about 2.6 million
    // angles over every binade down to 1e-38), and angles next to multiples of
    // pi/4, where the reduction cancels: sin_cos must equal sin and cos in long
    // double (64-bit significand) rounded to float. libm's sinf and cosf miss
    // on about 0.5% of such angles.
    std::vector<float> angles;
    for (uint32_t b = 0x00800000u; b <= std::bit_cast<uint32_t>(6.315f); b += 401) angles.push_back(std::bit_cast<float>(b));
    for (uint32_t b = 0x00800000u; b <= std::bit_cast<uint32_t>(0.786f); b += 401) angles.push_back(-std::bit_cast<float>(b));
    for (int k = -1; k <= 8; ++k) {
        float a = static_cast<float>(k * std::numbers::pi / 4);
        for (int s = 0; s < 64; ++s, a = std::nextafter(a, 10.0f)) angles.push_back(a);
    }
    ASSERT_GT(angles.size(), 1000000u);
    std::size_t wrong = 0;
    for (const float p : angles) {
        const SinCos sc = sin_cos(p);
        const auto x = static_cast<long double>(p);
        if (!same_bits(sc.sin, static_cast<float>(std::sin(x))) || !same_bits(sc.cos, static_cast<float>(std::cos(x)))) {
            if (++wrong <= 5) ADD_FAILURE() << "sin_cos(" << p << ") = " << sc.sin << ", " << sc.cos;
        }
    }
    EXPECT_EQ(wrong, 0u);
}

TEST(SinCos, LanesGiveTheScalarBits) {
    Pcg32 rng(3, 4);
    for (int round = 0; round < 20000; ++round) {
        lanes::F32 phi;
        for (int l = 0; l < W; ++l) phi[l] = (rng.next_float() * 7.1f - 0.8f) * (round % 7 == 0 ? 1e-3f : 1.0f);
        const lanes::SinCos v = lanes::sin_cos(phi);
        for (int l = 0; l < W; ++l) {
            const SinCos s = sin_cos(phi[l]);
            ASSERT_TRUE(same_bits(v.sin[l], s.sin) && same_bits(v.cos[l], s.cos)) << "phi " << phi[l];
        }
    }
}

TEST(SinCos, BeyondItsRangeDefersToLibm) {
    EXPECT_EQ(sin_cos(100.0f).sin, std::sin(100.0f));
    EXPECT_TRUE(std::isnan(sin_cos(std::nanf("")).cos));
}

TEST(SinCosDouble, WithinTwoToTheMinus51OfTheTrueValues) {
    // Doubles 2^-12 apart in ratio over (1e-300, 8.4], and as many in [-1.2, 0):
    // sin and cos within 2^-51 of the values in long double, relative to them
    // (its documented accuracy; the largest error seen is 1.07 2^-52).
    std::size_t tried = 0;
    for (double x = 1e-300; x <= 8.4; x = x * (1.0 + 0x1p-12)) {
        for (const double v : {x, -x * 0.142857}) {
            const SinCosDouble sc = sin_cos_double(v);
            const auto lv = static_cast<long double>(v);
            const long double s = std::sin(lv), c = std::cos(lv);
            ASSERT_LE(std::abs(sc.sin - s), 0x1p-51L * std::abs(s)) << "sin " << v;
            ASSERT_LE(std::abs(sc.cos - c), 0x1p-51L * std::abs(c)) << "cos " << v;
            ++tried;
        }
    }
    EXPECT_GT(tried, 1000000u);
}

TEST(SinCosDouble, LanesGiveTheScalarBits) {
    Pcg32 rng(13, 14);
    for (int round = 0; round < 20000; ++round) {
        lanes::F64 x;
        for (int l = 0; l < W; ++l) x[l] = (rng.next_double() * 9.5 - 1.2) * (round % 7 == 0 ? 1e-6 : 1.0);
        const lanes::SinCosDouble v = lanes::sin_cos_double(x);
        for (int l = 0; l < W; ++l) {
            const SinCosDouble s = sin_cos_double(x[l]);
            ASSERT_TRUE(std::bit_cast<uint64_t>(v.sin[l]) == std::bit_cast<uint64_t>(s.sin) &&
                        std::bit_cast<uint64_t>(v.cos[l]) == std::bit_cast<uint64_t>(s.cos))
                << "x " << x[l];
        }
    }
}

TEST(LanePcg32, StepsAsScalarGenerators) {
    lanes::Pcg32Lanes v;
    std::vector<Pcg32> scalar;
    for (int l = 0; l < W; ++l) {
        scalar.emplace_back(static_cast<uint64_t>(l) * 977, 12345 + static_cast<uint64_t>(l));
        v.state[l] = scalar.back().state();
        v.inc[l] = scalar.back().increment();
    }
    for (int i = 0; i < 1000; ++i) {
        const lanes::U32 a = v.next_u32();
        const lanes::U64 b = v.next_u64();
        for (int l = 0; l < W; ++l) {
            ASSERT_EQ(a[l], scalar[static_cast<std::size_t>(l)].next_u32());
            ASSERT_EQ(b[l], scalar[static_cast<std::size_t>(l)].next_u64());
        }
    }
}

// The scalar reference of validate's uniform_float_from_bits, restated: the
// 24 leading bits of w, times 2^-64 (the sampling library has no scalar form).
float leading_bits_times_2_64(uint64_t w) {
    if (w == 0) return 0.0f;
    const int msb = 63 - std::countl_zero(w);
    const uint64_t kept = msb >= 23 ? (w >> (msb - 23)) << (msb - 23) : w;
    return static_cast<float>(std::ldexp(static_cast<long double>(kept), -64));
}

TEST(LaneUniformFloat, LeadingTwentyFourBitsOfEveryShape) {
    std::vector<uint64_t> words = {0, 1, 2, 3, ~uint64_t{0}, ~uint64_t{0} - 1, uint64_t{1} << 63};
    for (int k = 0; k < 64; ++k) {
        const uint64_t p = uint64_t{1} << k;
        for (const uint64_t w : {p, p - 1, p + 1, p | (p >> 1), p | (p >> 24), p | (p >> 23)}) words.push_back(w);
    }
    Pcg32 rng(5, 6);
    for (int i = 0; i < 4096; ++i) words.push_back(rng.next_u64() >> (i % 64));
    while (words.size() % W) words.push_back(0);
    for (std::size_t i = 0; i < words.size(); i += W) {
        lanes::U64 w;
        for (int l = 0; l < W; ++l) w[l] = words[i + static_cast<std::size_t>(l)];
        const lanes::F32 f = lanes::uniform_float_from_bits(w);
        for (int l = 0; l < W; ++l) ASSERT_TRUE(same_bits(f[l], leading_bits_times_2_64(w[l]))) << "w " << w[l];
    }
}

/// How many inputs the lane form maps to other bits than the scalar warp.
template <typename Scalar, typename Lanes>
std::size_t lane_differences(const Scalar& scalar, const Lanes& lane_form) {
    // Edge values of each coordinate (0, powers of two down to 2^-40, the
    // centre, 1 - 2^-24) against each other, then uniform inputs.
    std::vector<float> edges = {0.0f, 0.5f, kOneMinusEpsilon, 0.25f, 0.75f, std::nextafter(0.5f, 0.0f),
                                std::nextafter(0.5f, 1.0f)};
    for (int k = 1; k <= 40; ++k) edges.push_back(std::ldexp(1.0f, -k));
    std::vector<Point2f> inputs;
    for (const float a : edges)
        for (const float b : edges) inputs.push_back({a, b});
    Pcg32 rng(9, 10);
    for (int i = 0; i < 200000; ++i) inputs.push_back({rng.next_float(), rng.next_float()});
    while (inputs.size() % W) inputs.push_back({0.5f, 0.5f});
    std::size_t differ = 0;
    for (std::size_t i = 0; i < inputs.size(); i += W) {
        lanes::F32 u0, u1;
        for (int l = 0; l < W; ++l) {
            u0[l] = inputs[i + static_cast<std::size_t>(l)].x;
            u1[l] = inputs[i + static_cast<std::size_t>(l)].y;
        }
        const lanes::Points p = lane_form(u0, u1);
        for (int l = 0; l < W; ++l) {
            const auto s = scalar.sample({u0[l], u1[l]});
            float sz = 0.0f;
            if constexpr (requires { s.z; }) sz = s.z;
            differ += !same_bits(p.x[l], s.x) || !same_bits(p.y[l], s.y) || !same_bits(p.z[l], sz);
        }
    }
    return differ;
}

TEST(LaneWarps, GiveTheScalarWarpsBits) {
    EXPECT_EQ(lane_differences(UniformDiskPolar{}, lanes::UniformDiskPolarLanes{}), 0u);
    EXPECT_EQ(lane_differences(UniformDiskConcentric{}, lanes::UniformDiskConcentricLanes{}), 0u);
    EXPECT_EQ(lane_differences(CosineHemisphere{}, lanes::CosineHemisphereLanes{}), 0u);
    EXPECT_EQ(lane_differences(UniformHemisphere{}, lanes::UniformHemisphereLanes{}), 0u);
    EXPECT_EQ(lane_differences(UniformSphere{}, lanes::UniformSphereLanes{}), 0u);
    for (const float n : {0.0f, 0.5f, 1.0f, 4.0f, 50.0f, 1e4f})
        EXPECT_EQ(lane_differences(CosinePowerHemisphere(n), lanes::CosinePowerHemisphereLanes{n}), 0u)
            << "exponent " << n;
    for (const float c : {-1.0f, -0.5f, 0.0f, 0.3f, 0.99f, 0.99999f})
        EXPECT_EQ(lane_differences(UniformCone(c), lanes::UniformConeLanes{c}), 0u) << "cos_theta_max " << c;
    for (const auto& [ax, ay] : {std::pair{1e-4f, 1e-4f}, {0.05f, 0.05f}, {0.3f, 0.05f}, {1.0f, 1.0f}, {0.05f, 0.4f},
                                {1e4f, 1e4f}}) {
        const TrowbridgeReitz tr(ax, ay);
        EXPECT_EQ(lane_differences(tr.normals(), lanes::TrowbridgeReitzNormalsLanes{ax, ay}), 0u)
            << "alpha " << ax << ", " << ay;
        for (const float theta : {0.0f, 1e-3f, 0.5f, 1.0f, 1.4835f, 1.5707964f}) {  // normal incidence to grazing
            const auto visible = tr.visible_normals({std::sin(theta), 0.3f * std::sin(theta), std::cos(theta)});
            EXPECT_EQ(lane_differences(visible, lanes::TrowbridgeReitzVisibleNormalsLanes(visible)), 0u)
                << "alpha " << ax << ", " << ay << ", theta_o " << theta;
        }
    }
}

TEST(LaneWarps, ComparisonCanFail) {
    // A lane form that differs from its scalar twin by one rounding is caught.
    struct OffByOneUlp {
        lanes::Points operator()(lanes::F32 u0, lanes::F32 u1) const {
            lanes::Points p = lanes::CosineHemisphereLanes{}(u0, u1);
            p.z = p.z * (1.0f + 0x1p-23f);
            return p;
        }
    };
    EXPECT_GT(lane_differences(CosineHemisphere{}, OffByOneUlp{}), 100000u);
}

TEST(LaneWarps, PowerComparisonCanFail) {
    // The cosine power's lane form with its power one ulp off in one lane of
    // eight, or with the uniform hemisphere's z = u.x (exponent 0 for 4), is caught.
    struct PowerOffByOneUlp {
        lanes::Points operator()(lanes::F32 u0, lanes::F32 u1) const {
            lanes::F32 z = lanes::pow(u0, 1.0f / 5.0f);
            z[3] = std::nextafter(z[3], 0.0f);
            return lanes::UniformHemisphereLanes{}(z, u1);
        }
    };
    EXPECT_GT(lane_differences(CosinePowerHemisphere(4.0f), PowerOffByOneUlp{}), 20000u);
    EXPECT_GT(lane_differences(CosinePowerHemisphere(4.0f), lanes::CosinePowerHemisphereLanes{0.0f}), 190000u);
}

}  // namespace
}  // namespace warpcheck
