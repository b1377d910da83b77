// PiecewiseConstant1D/2D and the tabulation helper: known values, zero and
// negative inputs, sample/pdf agreement at bucket boundaries, round trips.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "sampling/pcg32.h"
#include "sampling/piecewise_constant.h"
#include "sampling/tabulate.h"

namespace warpcheck {
namespace {

const float kPiecewiseEdges[] = {0.0f, 0x1p-24f, 0.25f, 0.5f, 0.75f, kOneMinusEpsilon};

TEST(PiecewiseConstant1D, RejectsBadInput) {
    const std::vector<float> ok{1.0f, 2.0f};
    EXPECT_THROW(PiecewiseConstant1D(std::vector<float>{}, 0.0f, 1.0f), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant1D(ok, 1.0f, 1.0f), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant1D(ok, 0.0f, std::numeric_limits<float>::infinity()), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant1D(std::vector<float>{1.0f, std::nanf("")}, 0.0f, 1.0f), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant1D(std::vector<float>{std::numeric_limits<float>::infinity()}, 0.0f, 1.0f),
                 std::invalid_argument);
}

TEST(PiecewiseConstant1D, KnownValues) {
    const PiecewiseConstant1D d(std::vector<float>{1.0f, 0.0f, 3.0f}, 0.0f, 3.0f);
    EXPECT_FLOAT_EQ(d.integral(), 4.0f);
    EXPECT_FLOAT_EQ(d.pdf(0.5f), 0.25f);
    EXPECT_EQ(d.pdf(1.5f), 0.0f);
    EXPECT_FLOAT_EQ(d.pdf(2.5f), 0.75f);
    EXPECT_EQ(d.pdf(-0.1f), 0.0f);
    EXPECT_EQ(d.pdf(3.1f), 0.0f);
    EXPECT_EQ(d.cdf()[0], 0.0f);
    EXPECT_FLOAT_EQ(d.cdf()[1], 0.25f);
    EXPECT_FLOAT_EQ(d.cdf()[2], 0.25f);
    EXPECT_EQ(d.cdf()[3], 1.0f);
    // u = 0.25 is the start of the third bucket (the second has no mass).
    const auto s = d.sample(0.25f);
    EXPECT_EQ(s.offset, 2);
    EXPECT_FLOAT_EQ(s.x, 2.0f);
    EXPECT_FLOAT_EQ(s.pdf, 0.75f);
    EXPECT_FLOAT_EQ(d.sample(0.125f).x, 0.5f);
    EXPECT_FLOAT_EQ(d.invert(2.5f), 0.625f);
}

TEST(PiecewiseConstant1D, NegativeValuesCarryNoMass) {
    const PiecewiseConstant1D d(std::vector<float>{2.0f, -5.0f, 2.0f}, -1.0f, 2.0f);
    EXPECT_FLOAT_EQ(d.integral(), 4.0f);
    EXPECT_EQ(d.pdf(0.5f), 0.0f);
    Pcg32 rng(1, 1);
    for (int i = 0; i < 100000; ++i) EXPECT_NE(d.sample(rng.next_float()).offset, 1);
}

TEST(PiecewiseConstant1D, AllZeroIsUniform) {
    for (const std::vector<float>& f : {std::vector<float>{0.0f, 0.0f, 0.0f, 0.0f}, std::vector<float>{-1.0f, -2.0f}}) {
        const PiecewiseConstant1D d(f, 1.0f, 3.0f);
        EXPECT_EQ(d.integral(), 0.0f);
        for (float u : kPiecewiseEdges) {
            const auto s = d.sample(u);
            EXPECT_FLOAT_EQ(s.x, 1.0f + 2.0f * u);
            EXPECT_FLOAT_EQ(s.pdf, 0.5f);
            EXPECT_FLOAT_EQ(d.pdf(s.x), 0.5f);
            EXPECT_NEAR(d.invert(s.x), u, 1e-7);
        }
    }
}

TEST(PiecewiseConstant1D, SampleAgreesWithPdfAndInvertEverywhere) {
    // Many buckets, zeros, a wide range of values, an off-centre range: every
    // sample's bucket, pdf and inverse agree, at the buckets' edges too.
    std::vector<float> f;
    for (int i = 0; i < 1000; ++i) f.push_back(i % 7 == 3 ? 0.0f : std::exp(std::sin(0.1f * i) * 6.0f));
    const PiecewiseConstant1D d(f, -0.3f, 1.7f);
    Pcg32 rng(2, 3);
    std::vector<float> us(std::begin(kPiecewiseEdges), std::end(kPiecewiseEdges));
    for (std::size_t i = 0; i <= f.size(); ++i) us.push_back(std::min(d.cdf()[i], kOneMinusEpsilon));
    for (int i = 0; i < 200000; ++i) us.push_back(rng.next_float());
    for (float u : us) {
        const auto s = d.sample(u);
        ASSERT_GE(s.x, d.min());
        ASSERT_LE(s.x, d.max());
        ASSERT_EQ(d.offset(s.x), s.offset) << u;
        ASSERT_GT(s.pdf, 0.0f) << u;
        ASSERT_EQ(d.pdf(s.x), s.pdf) << u;
        ASSERT_LE(std::abs(d.invert(s.x) - u), 1e-5f) << u;
    }
}

TEST(PiecewiseConstant2D, KnownValuesAndNormalisation) {
    // 3 x 2 grid over [0, 3] x [0, 1]; the second row is empty.
    const std::vector<float> f{1.0f, 2.0f, 1.0f, 0.0f, 0.0f, 0.0f};
    const PiecewiseConstant2D d(f, 3, 2, 0.0f, 3.0f, 0.0f, 1.0f);
    EXPECT_FLOAT_EQ(d.integral(), 2.0f);  // (1 + 2 + 1) * cell area 0.5
    EXPECT_FLOAT_EQ(d.pdf({1.5f, 0.25f}), 1.0f);
    EXPECT_FLOAT_EQ(d.pdf({0.5f, 0.25f}), 0.5f);
    EXPECT_EQ(d.pdf({0.5f, 0.75f}), 0.0f);
    Pcg32 rng(4, 5);
    for (int i = 0; i < 100000; ++i) {
        const Point2f u{rng.next_float(), rng.next_float()};
        const auto s = d.sample(u);
        ASSERT_EQ(s.offset_y, 0);
        ASSERT_EQ(d.pdf(s.p), s.pdf);
        const Point2f back = d.invert(s.p);
        ASSERT_LE(std::max(std::abs(back.x - u.x), std::abs(back.y - u.y)), 1e-6f);
    }
}

TEST(PiecewiseConstant2D, AllZeroIsUniform) {
    const PiecewiseConstant2D d(std::vector<float>(6, 0.0f), 3, 2, -1.0f, 1.0f, 0.0f, 4.0f);
    EXPECT_EQ(d.integral(), 0.0f);
    for (float a : kPiecewiseEdges)
        for (float b : kPiecewiseEdges) {
            const auto s = d.sample({a, b});
            EXPECT_FLOAT_EQ(s.pdf, 0.125f);
            EXPECT_FLOAT_EQ(d.pdf(s.p), 0.125f);
            EXPECT_FLOAT_EQ(s.p.x, -1.0f + 2.0f * a);
            EXPECT_FLOAT_EQ(s.p.y, 4.0f * b);
        }
}

TEST(PiecewiseConstant2D, RejectsBadInput) {
    EXPECT_THROW(PiecewiseConstant2D(std::vector<float>(5, 1.0f), 3, 2, 0.0f, 1.0f, 0.0f, 1.0f), std::invalid_argument);
    EXPECT_THROW(PiecewiseConstant2D(std::vector<float>{}, 0, 2, 0.0f, 1.0f, 0.0f, 1.0f), std::invalid_argument);
}

TEST(Tabulate, AveragesAreExactForLinearFunctions) {
    // The midpoint rule is exact for linear f: the bucket average of 2x + 1.
    const auto t = tabulate([](double x) { return 2.0 * x + 1.0; }, 0.0, 1.0, 4, 3);
    ASSERT_EQ(t.size(), 4u);
    for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(t[static_cast<std::size_t>(i)], 2.0f * (i + 0.5f) / 4.0f + 1.0f);
    const auto b = tabulate_buckets([](double x) { return 2.0 * x + 1.0; }, 0.0, 1.0, 4, 3);
    EXPECT_DOUBLE_EQ(b[1].min, 1.5);
    EXPECT_DOUBLE_EQ(b[1].max, 2.0);
    EXPECT_DOUBLE_EQ(b[1].mean, 1.75);
    const auto t2 = tabulate_2d([](double x, double y) { return x + 10.0 * y; }, 0.0, 2.0, 0.0, 1.0, 2, 2, 2);
    ASSERT_EQ(t2.size(), 4u);
    EXPECT_FLOAT_EQ(t2[0], 0.5f + 2.5f);
    EXPECT_FLOAT_EQ(t2[3], 1.5f + 7.5f);
}

TEST(Tabulate, SupersamplingConvergesToTheIntegral) {
    // A tabulated table's integral approaches the function's (here int_0^pi sin = 2).
    const auto t = tabulate([](double x) { return std::sin(x); }, 0.0, std::numbers::pi, 64, 16);
    const PiecewiseConstant1D d(t, 0.0f, std::numbers::pi_v<float>);
    EXPECT_NEAR(d.integral(), 2.0, 1e-5);
}

}  // namespace
}  // namespace warpcheck
