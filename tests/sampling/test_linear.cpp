// Linear and bilinear warps: known values, normalisation, inverses, parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "sampling/linear.h"

namespace warpcheck {
namespace {

TEST(Linear, KnownValues) {
    EXPECT_EQ(Linear(0.0f, 1.0f).sample(0.0f), 0.0f);           // 0/0 in the naive formula
    EXPECT_NEAR(Linear(0.0f, 1.0f).sample(0.25f), 0.5f, 1e-7);  // density 2x: CDF x^2
    EXPECT_NEAR(Linear(1.0f, 1.0f).sample(0.5f), 0.5f, 1e-7);   // constant density
    EXPECT_FLOAT_EQ(Linear(1.0f, 3.0f).pdf(1.0f), 1.5f);
    EXPECT_FLOAT_EQ(Linear(1.0f, 3.0f).pdf(0.0f), 0.5f);
    EXPECT_EQ(Linear(1.0f, 3.0f).pdf(1.5f), 0.0f);
}

TEST(Linear, InverseAndDensityAgree) {
    for (auto [a, b] : {std::pair{1.0f, 3.0f}, std::pair{0.0f, 1.0f}, std::pair{5.0f, 0.0f}}) {
        double integral = 0.0;
        const int n = 10000;
        for (int i = 0; i < n; ++i) integral += Linear(a, b).pdf((i + 0.5f) / n) / n;
        EXPECT_NEAR(integral, 1.0, 1e-6) << a << " " << b;
        for (float u : {0x1p-24f, 0.1f, 0.5f, 0.9f, kOneMinusEpsilon}) {
            const float back = Linear(a, b).invert(Linear(a, b).sample(u));
            EXPECT_NEAR(back, u, 1e-6) << a << " " << b << " u=" << u;
        }
    }
}

TEST(Bilinear, DensityIntegratesToOneAndRoundTrips) {
    const Bilinear patch(1.0f, 4.0f, 0.5f, 2.0f);
    double integral = 0.0;
    const int n = 400;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) integral += patch.pdf({(i + 0.5f) / n, (j + 0.5f) / n}) / (n * n);
    EXPECT_NEAR(integral, 1.0, 1e-5);
    const Point2f back = patch.invert(patch.sample({0.3f, 0.7f}));
    EXPECT_NEAR(back.x, 0.3f, 1e-6);
    EXPECT_NEAR(back.y, 0.7f, 1e-6);
    EXPECT_FLOAT_EQ(Bilinear(1, 1, 1, 1).pdf({0.2f, 0.9f}), 1.0f);
}

TEST(Bilinear, InvalidWeightsAreRejected) {
    EXPECT_THROW(Bilinear(0, 0, 0, 0), std::invalid_argument);
    EXPECT_THROW(Bilinear(-1, 1, 1, 1), std::invalid_argument);
    EXPECT_THROW(Bilinear(std::numeric_limits<float>::quiet_NaN(), 1, 1, 1), std::invalid_argument);
    EXPECT_THROW(Bilinear(std::numeric_limits<float>::infinity(), 1, 1, 1), std::invalid_argument);
}

}  // namespace
}  // namespace warpcheck
