// Streaming moments and the t-test of a mean against a reference.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "chi2/mean_test.h"

namespace warpcheck::chi2 {
namespace {

TEST(Moments, MeanAndVarianceOfKnownValues) {
    Moments m;
    for (double x : {1.0, 2.0, 3.0, 4.0}) m.add(x);
    EXPECT_EQ(m.n, 4u);
    EXPECT_DOUBLE_EQ(m.mean, 2.5);
    EXPECT_DOUBLE_EQ(m.variance(), 5.0 / 3.0);
}

TEST(Moments, MergedPartsGiveTheWholesMoments) {
    Moments whole, a, b;
    for (int i = 0; i < 100; ++i) {
        const double x = std::sin(i * 0.7) * 3 + i * 0.01;
        whole.add(x);
        (i < 37 ? a : b).add(x);
    }
    a.merge(b);
    EXPECT_EQ(a.n, whole.n);
    EXPECT_NEAR(a.mean, whole.mean, 1e-14);
    EXPECT_NEAR(a.variance(), whole.variance(), 1e-12);
    Moments empty;
    empty.merge(a);
    EXPECT_EQ(empty.mean, a.mean);
}

TEST(MeanTest, KnownTStatisticAndTwoSidedPValue) {
    Moments m;
    for (double x : {1.0, 2.0, 3.0, 4.0}) m.add(x);
    // t = (2.5 - 1) / sqrt(5/3 / 4) = 2.3238; two-sided p with 3 dof = 0.1027 (t tables).
    const MeanTest t = mean_test(m, 1.0, 0.0);
    EXPECT_NEAR(t.t, 2.32379, 1e-5);
    EXPECT_NEAR(t.p_value, 0.10274, 1e-4);
    EXPECT_NEAR(mean_test(m, 2.5, 0.0).p_value, 1.0, 1e-12);
}

TEST(MeanTest, ReferenceUncertaintyWidensTheStandardError) {
    Moments m;
    for (double x : {1.0, 2.0, 3.0, 4.0}) m.add(x);
    EXPECT_GT(mean_test(m, 1.0, 1.0).p_value, mean_test(m, 1.0, 0.0).p_value);
}

TEST(MeanTest, ConstantSamplesAgreeOnlyWithTheirValue) {
    Moments m;
    for (int i = 0; i < 10; ++i) m.add(0.75);
    EXPECT_EQ(mean_test(m, 0.75, 0.0).p_value, 1.0);
    EXPECT_EQ(mean_test(m, 0.8, 0.0).p_value, 0.0);
    EXPECT_GT(mean_test(m, 0.75 + 1e-9, 1e-8).p_value, 0.9);
}

TEST(MeanTest, NaNNeverPasses) {
    Moments m;
    for (double x : {1.0, std::numeric_limits<double>::quiet_NaN(), 3.0}) m.add(x);
    EXPECT_TRUE(std::isnan(mean_test(m, 1.0, 0.0).p_value));
    Moments few;
    few.add(1.0);
    EXPECT_TRUE(std::isnan(mean_test(few, 1.0, 0.0).p_value));
}

}  // namespace
}  // namespace warpcheck::chi2
