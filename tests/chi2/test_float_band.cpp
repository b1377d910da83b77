// The float resolution of domain parameters (chi2/float_band.h): the band of a
// parameter that is one float coordinate is exactly that coordinate's float
// neighbours; the first-order bands of phi and r^2 hold every move of the
// point's floats within the stated steps; and the number of steps is what a
// renderer's cone formula needs.
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "chi2/float_band.h"

namespace warpcheck::chi2 {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

float steps_from(float c, int steps, float towards) {
    for (int k = 0; k < steps; ++k) c = std::nextafter(c, towards);
    return c;
}

TEST(FloatResolution, OneCoordinateParametersAreTheirFloatNeighbours) {
    // A cap's cos theta away from the poles is z itself, stepped as a float.
    const Binning cap(Domain::sphere(), {4, 4});
    const FloatResolution z(cap, 1, 2);
    EXPECT_EQ(z.coordinate(), -1);  // z, or near a pole x and y: not one coordinate
    const std::array<float, 3> p = {0.8f, 0.5099f, 0.3f};
    const ParameterBand b = z.band(p);
    EXPECT_EQ(b.value, static_cast<double>(p[2]));
    EXPECT_EQ(b.lo, static_cast<double>(steps_from(p[2], 2, -kInf)));
    EXPECT_EQ(b.hi, static_cast<double>(steps_from(p[2], 2, kInf)));
    // Near the pole it is read off x and y: 1 - cos theta within 5 2^-24 of
    // itself per step, far finer than z's own float step (2^-24).
    const double theta = 2e-3;
    const std::array<float, 3> near = {static_cast<float>(std::sin(theta)), 0.0f, static_cast<float>(std::cos(theta))};
    const ParameterBand n = z.band(near);
    EXPECT_NEAR(1.0 - n.value, 1.0 - std::cos(theta), 1e-7 * (1.0 - std::cos(theta)));
    EXPECT_NEAR((n.hi - n.value) / (2 * 5 * 0x1p-24 * (1.0 - n.value)), 1.0, 1e-3);
    EXPECT_LT(n.hi - n.lo, 0x1p-24);
    const ParameterBand top = z.band({0.0f, 0.0f, 1.0f});  // the pole itself: no width
    EXPECT_EQ(top.value, 1.0);
    EXPECT_EQ(top.hi, top.lo);
    EXPECT_FALSE(top.wraps);

    // A half-line's parameter t = d / (s + d) of the stepped floats.
    const Binning line(Domain::half_line(0.0), {8, 1, 2.0});
    const FloatResolution t(line, 0, 1);
    const float x = 3.7f;
    const ParameterBand tb = t.band({x, 0.0f, 0.0f});
    EXPECT_EQ(tb.value, line.parameters_of({x, 0.0, 0.0})[0]);
    EXPECT_EQ(tb.lo, line.parameters_of({std::nextafter(x, -kInf), 0.0, 0.0})[0]);
    EXPECT_EQ(tb.hi, line.parameters_of({std::nextafter(x, kInf), 0.0, 0.0})[0]);
    EXPECT_LT(tb.lo, tb.value);
    EXPECT_GT(tb.hi, tb.value);
    // The largest float's step up has no parameter: the band is open above.
    EXPECT_EQ(t.band({std::numeric_limits<float>::max(), 0.0f, 0.0f}).hi, std::numeric_limits<double>::infinity());

    const Binning box(Domain::box(-1.0, 1.0, 0.0, 2.0), {4, 4});
    EXPECT_EQ(FloatResolution(box, 1, 1).band({0.5f, 1.5f, 0.0f}).hi, static_cast<double>(std::nextafter(1.5f, kInf)));
    EXPECT_THROW(FloatResolution(box, 2, 1), std::invalid_argument);
    EXPECT_THROW(FloatResolution(box, 0, 0), std::invalid_argument);
}

// A triangle's parameters (s, t) mix x and y: the value is the binning's own
// parameter of the point (not a coordinate; reading x as s made the unbinned
// check fail a correct triangle at KS 0.22), and the band holds every move of
// both floats within the steps, including near the first vertex where t's
// band widens without bound (so no model replaces the per-sample bands).
TEST(FloatResolution, TriangleParametersAreProbedOverBothCoordinates) {
    const Binning tri(Domain::triangle({0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}), {4, 4});
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int axis = 0; axis < 2; ++axis) {
        const FloatResolution r(tri, axis, 2);
        EXPECT_EQ(r.coordinate(), -1);
        EXPECT_EQ(r.half_width_at(0.5), std::numeric_limits<double>::infinity());
        for (int i = 0; i < 2000; ++i) {
            float x = u(rng), y = u(rng);
            if (x + y >= 1.0f) x = 1.0f - x, y = 1.0f - y;
            if (i < 10) x = std::ldexp(x, -20), y = std::ldexp(y, -20);  // next to the vertex at the origin
            const ParameterBand b = r.band({x, y, 0.0f});
            ASSERT_EQ(b.value, tri.parameters_of({x, y, 0.0})[static_cast<std::size_t>(axis)]);
            for (int dx = -2; dx <= 2; ++dx)
                for (int dy = -2; dy <= 2; ++dy) {
                    const float mx = steps_from(x, std::abs(dx), dx < 0 ? -kInf : kInf);
                    const float my = steps_from(y, std::abs(dy), dy < 0 ? -kInf : kInf);
                    const double v = tri.parameters_of({mx, my, 0.0})[static_cast<std::size_t>(axis)];
                    // First order: allow the band's own width times 1e-6 for curvature.
                    const double slack = 1e-6 * (b.hi - b.lo);
                    EXPECT_TRUE(v >= b.lo - slack && v <= b.hi + slack) << axis << " " << x << " " << y;
                }
        }
    }
}

TEST(FloatResolution, BandEndsAreTheFloatsThatNextafterReaches) {
    // Random bit patterns of every sign and scale, zeros, subnormals and the
    // largest float: the ends are nextafter's, step by step.
    const Binning line(Domain::interval(-4.0, 4.0), {8, 1});
    std::mt19937_64 rng(3);
    std::vector<float> values = {0.0f, -0.0f, std::numeric_limits<float>::denorm_min(),
                                 -std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::max(),
                                 -std::numeric_limits<float>::max(), 1.0f, -1.0f};
    for (int i = 0; i < 100000; ++i) {
        const float v = std::bit_cast<float>(static_cast<uint32_t>(rng()));
        if (std::isfinite(v)) values.push_back(v);
    }
    for (int steps : {1, 2, 3}) {
        const FloatResolution x(line, 0, steps);
        for (float v : values) {
            const ParameterBand b = x.band({v, 0.0f, 0.0f});
            EXPECT_EQ(b.lo, static_cast<double>(steps_from(v, steps, -kInf))) << v;
            EXPECT_EQ(b.hi, static_cast<double>(steps_from(v, steps, kInf))) << v;
        }
    }
}

/// The float `steps` steps from c, `k` of the 2 steps + 1 choices -steps .. steps.
float moved(float c, int k, int steps) { return k < steps ? steps_from(c, steps - k, -kInf) : steps_from(c, k - steps, kInf); }

TEST(FloatResolution, AzimuthAndRadiusBandsHoldEveryMoveOfTheFloats) {
    // Random points of every scale: moving x and y by up to 2 float steps each,
    // in every combination, keeps phi and r^2 within their stated bands.
    const Binning disk(Domain::unit_disk(), {8, 8});
    const FloatResolution phi(disk, 0, 2), r2(disk, 1, 2);
    EXPECT_EQ(phi.coordinate(), -1);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> angle(0.0f, 6.2831f), scale(-20.0f, 0.0f);
    int wrapped = 0;
    for (int i = 0; i < 20000; ++i) {
        const float r = std::exp2(scale(rng)), a = angle(rng);
        const std::array<float, 3> p = {r * std::cos(a), r * std::sin(a), 0.0f};
        const ParameterBand bp = phi.band(p), br = r2.band(p);
        wrapped += bp.wraps;
        for (int kx = 0; kx <= 4; ++kx)
            for (int ky = 0; ky <= 4; ++ky) {
                const std::array<float, 3> q = {moved(p[0], kx, 2), moved(p[1], ky, 2), 0.0f};
                double v = phi.value(q);
                if (bp.wraps && v > std::numbers::pi) v -= 2.0 * std::numbers::pi;  // the other end of the circle
                if (!bp.wraps) {
                    EXPECT_GE(v, bp.lo) << i;
                }
                EXPECT_LE(v, bp.hi) << i;
                EXPECT_GE(r2.value(q), br.lo) << i;
                EXPECT_LE(r2.value(q), br.hi) << i;
            }
    }
    // Where the band crosses phi = 0 it says so.
    EXPECT_TRUE(phi.band({1.0f, 1e-9f, 0.0f}).wraps);
    EXPECT_TRUE(phi.band({1.0f, -1e-9f, 0.0f}).wraps);
    EXPECT_FALSE(phi.band({1.0f, 1e-3f, 0.0f}).wraps);
    std::printf("%d of 20000 random points had an azimuth band across phi = 0\n", wrapped);
}

/// The real number w 2^-64 rounded down to a float, as the runner draws u.
float unit_float(uint64_t w) {
    if (w == 0) return 0.0f;
    const int msb = 63 - std::countl_zero(w);
    const uint64_t significand = msb >= 23 ? w >> (msb - 23) : w << (23 - msb);
    return std::bit_cast<float>(static_cast<uint32_t>(msb - 64 + 127) << 23 |
                                (static_cast<uint32_t>(significand) & 0x7fffffu));
}

TEST(FloatResolution, TwoStepsHoldPbrtsConeFormulaAndOneDoesNot) {
    // pbrt-v4's cone: cos theta = (1 - u) + u cos_max in float. Its three
    // roundings of half an ulp put the result up to 1.25 ulp from the exact
    // value of the same formula: within the default 2 float steps always,
    // beyond 1 step (the strict setting: correctly rounded) for ~1% of inputs.
    std::mt19937_64 rng(9);
    for (double degrees : {0.25, 1.0, 30.0}) {
        const auto cos_max = static_cast<float>(std::cos(degrees * std::numbers::pi / 180.0));
        int beyond_one = 0, beyond_two = 0;
        for (int i = 0; i < 1'000'000; ++i) {
            const float u = unit_float(rng());
            const float z = (1.0f - u) + u * cos_max;
            const long double exact = (1.0L - u) + static_cast<long double>(u) * cos_max;
            beyond_one += !(exact >= std::nextafter(z, -kInf) && exact <= std::nextafter(z, kInf));
            beyond_two += !(exact >= steps_from(z, 2, -kInf) && exact <= steps_from(z, 2, kInf));
        }
        std::printf("cone of %g degrees: %d of 10^6 outputs beyond 1 float step of the exact value, %d beyond 2\n",
                    degrees, beyond_one, beyond_two);
        EXPECT_EQ(beyond_two, 0);
        if (degrees < 10.0) {
            EXPECT_GT(beyond_one, 1000);
        }
    }
}

}  // namespace
}  // namespace warpcheck::chi2
