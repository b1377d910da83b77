// The largest-residual statistic: finds the deviating cell, corrects for the
// number of cells, and is insensitive to cells with no expected count.
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "chi2/local_residual.h"
#include "chi2/min_p.h"

namespace warpcheck::chi2 {
namespace {

TEST(LocalResidual, FindsTheCellAndCorrectsForTheirNumber) {
    std::vector<uint64_t> counts(1000, 1000);
    std::vector<double> expected(1000, 1000.0);
    counts[417] = 1200;  // 6.3 standard deviations
    counts[0] = 1000 - 100;
    const LocalResidual r = largest_cell_residual(counts, expected, 1'000'000);
    EXPECT_EQ(r.cell, 417u);
    EXPECT_NEAR(r.residual, 200.0 / std::sqrt(1000.0), 1e-12);
    EXPECT_EQ(r.cells_tested, 1000u);
    EXPECT_LT(r.cell_p_value, 1e-8);
    EXPECT_NEAR(r.p_value, -std::expm1(1000.0 * std::log1p(-r.cell_p_value)), 1e-15);
    EXPECT_GT(r.p_value, 500.0 * r.cell_p_value);
}

TEST(LocalResidual, ExactCountsPassAndEmptyCellsAreSkipped) {
    std::vector<uint64_t> counts = {500, 0, 500};
    std::vector<double> expected = {500.0, 0.0, 500.0};
    const LocalResidual r = largest_cell_residual(counts, expected, 1000);
    EXPECT_EQ(r.cells_tested, 2u);
    EXPECT_EQ(r.p_value, 1.0);
}

TEST(MinP, SidakAndWeightedBonferroni) {
    const std::vector<double> p = {0.5, 0.01, 0.2};
    EXPECT_NEAR(sidak_min_p(p), 1.0 - std::pow(0.99, 3), 1e-15);
    EXPECT_TRUE(std::isnan(sidak_min_p(std::vector<double>{0.5, std::nan("")})));
    EXPECT_TRUE(std::isnan(sidak_min_p(std::vector<double>{})));
    EXPECT_NEAR(weighted_min_p({0.4, 0.01}, {0.8, 0.2}), 0.05, 1e-15);
    EXPECT_EQ(weighted_min_p({0.9, 0.5}, {0.8, 0.2}), 1.0);
    EXPECT_TRUE(std::isnan(weighted_min_p({std::nan(""), 0.5}, {0.8, 0.2})));
}

}  // namespace
}  // namespace warpcheck::chi2
