// Pearson's statistic, pooling and p-values against an independent implementation.
//
// Reference values: computed once with SciPy 1.10.1 (Debian 12 python3-scipy,
// /usr/bin/python3), scipy.stats.chi2.sf(x, dof) for upper tails and
// scipy.stats.chisquare(f_obs, f_exp) for whole tables. Pooled tables were
// pooled by hand as documented at each test, then given to chisquare.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "chi2/pearson.h"

namespace warpcheck::chi2 {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Relative agreement with the reference (fails on NaN).
void expect_relative(double value, double reference, double tol) {
    EXPECT_TRUE(std::abs(value - reference) <= tol * std::abs(reference)) << value << " vs " << reference;
}

TEST(ChiSquareUpperTail, MatchesScipy) {
    struct Row {
        double x;
        double dof;
        double sf;  // scipy.stats.chi2.sf(x, dof), SciPy 1.10.1
    };
    const Row rows[] = {
        {0.5, 1, 0.47950012218695337},
        {3.841458820694124, 1, 0.04999999999999989},
        {25.0, 10, 0.005345505487134069},
        {1234.5, 1190, 0.1801859821616399},
        {150.0, 100, 0.0009039320423540184},
        {1e-3, 3, 0.9999915920809419},
        {80.0, 20, 3.925932226286184e-09},
        {2500.0, 2000, 1.074008023138619e-13},  // 1 - cdf would keep ~3 digits here
    };
    for (const Row& r : rows) expect_relative(chi_square_upper_tail(r.x, r.dof), r.sf, 1e-10);
}

TEST(ChiSquareUpperTail, EdgesAndInvalidInput) {
    EXPECT_EQ(chi_square_upper_tail(0.0, 4), 1.0);
    EXPECT_EQ(chi_square_upper_tail(std::numeric_limits<double>::infinity(), 4), 0.0);
    EXPECT_TRUE(std::isnan(chi_square_upper_tail(kNaN, 4)));
    EXPECT_TRUE(std::isnan(chi_square_upper_tail(1.0, 0)));
}

TEST(PearsonTest, ExactMatchGivesZeroStatistic) {
    const std::vector<double> counts = {10, 20, 30, 40, 7, 5};
    const PearsonResult r = pearson_test(counts, counts);
    EXPECT_EQ(r.statistic, 0.0);
    EXPECT_EQ(r.dof, 5);
    EXPECT_EQ(r.p_value, 1.0);
    EXPECT_EQ(r.pools, 0u);
}

TEST(PearsonTest, TablesMatchScipy) {
    {
        // scipy.stats.chisquare([16,18,16,14,12,12], [88/6]*6) -> (2.0, 0.8491450360846096)
        const std::vector<double> obs = {16, 18, 16, 14, 12, 12}, exp(6, 88.0 / 6.0);
        const PearsonResult r = pearson_test(obs, exp);
        expect_relative(r.statistic, 2.0, 1e-12);
        EXPECT_EQ(r.dof, 5);
        expect_relative(r.p_value, 0.8491450360846096, 1e-10);
    }
    {
        // scipy.stats.chisquare([43,52,54,40,11], [50,50,50,40,10]) -> (1.48, 0.8301782130065998)
        const std::vector<double> obs = {43, 52, 54, 40, 11}, exp = {50, 50, 50, 40, 10};
        const PearsonResult r = pearson_test(obs, exp);
        expect_relative(r.statistic, 1.48, 1e-12);
        EXPECT_EQ(r.dof, 4);
        expect_relative(r.p_value, 0.8301782130065998, 1e-10);
    }
}

TEST(PearsonTest, LeftoverPoolIsMergedNotDropped) {
    // Small cells (E < 5), by increasing E: 0.5, 1, 2, 3 close a pool at E = 6.5;
    // the leftover {4} (E = 4 < 5) joins that pool: E = 10.5, O = 0+3+1+4+6 = 14.
    // Table [95, 90, 47, 14] vs [100, 80, 55.5, 10.5]:
    // scipy.stats.chisquare -> (3.968468468468469, 0.26488915733335916)
    const std::vector<double> obs = {95, 90, 4, 1, 3, 0, 6, 47};
    const std::vector<double> exp = {100, 80, 3, 2, 1, 0.5, 4, 55.5};
    const PearsonResult r = pearson_test(obs, exp);
    EXPECT_EQ(r.terms, 4u);
    EXPECT_EQ(r.small_cells, 5u);
    EXPECT_EQ(r.pools, 1u);
    EXPECT_EQ(r.dof, 3);
    expect_relative(r.statistic, 3.968468468468469, 1e-12);
    expect_relative(r.p_value, 0.26488915733335916, 1e-10);
    // Every cell is in some term; the small ones share the pool's term.
    for (std::size_t c : {2u, 3u, 4u, 5u, 6u}) EXPECT_EQ(r.term_of_cell[c], 3u);
}

TEST(PearsonTest, LeftoverWithoutPoolJoinsSmallestRegularCell) {
    // Small cells total E = 3 < 5: they join the regular cell with the smallest E (20).
    // Terms: [50 vs 50], [22+1+2 vs 20+1+2]: statistic (25-23)^2/23.
    const std::vector<double> obs = {50, 22, 1, 2};
    const std::vector<double> exp = {50, 20, 1, 2};
    const PearsonResult r = pearson_test(obs, exp);
    EXPECT_EQ(r.terms, 2u);
    EXPECT_EQ(r.dof, 1);
    expect_relative(r.statistic, 4.0 / 23.0, 1e-14);
    EXPECT_EQ(r.term_of_cell[2], r.term_of_cell[1]);
}

TEST(PearsonTest, NoDegreesOfFreedomGivesNaN) {
    const std::vector<double> obs = {1, 2, 1}, exp = {1.5, 1.5, 1};
    const PearsonResult r = pearson_test(obs, exp);
    EXPECT_EQ(r.terms, 1u);
    EXPECT_EQ(r.dof, 0);
    EXPECT_TRUE(std::isnan(r.statistic));
    EXPECT_TRUE(std::isnan(r.p_value));
}

TEST(PearsonTest, NaNExpectationPoisonsTheResult) {
    const std::vector<double> obs = {10, 10, 10}, exp = {10, 10, kNaN};
    const PearsonResult r = pearson_test(obs, exp);
    EXPECT_FALSE(std::isfinite(r.statistic) && std::isfinite(r.p_value));
}

TEST(PearsonTest, LargeDeviationGivesTinyButPositivePValue) {
    std::vector<double> obs(100, 1000.0), exp(100, 1000.0);
    obs[0] = 1300;
    obs[1] = 700;
    const PearsonResult r = pearson_test(obs, exp);
    expect_relative(r.statistic, 180.0, 1e-14);
    EXPECT_GT(r.p_value, 0.0);
    EXPECT_LT(r.p_value, 1e-5);
}

}  // namespace
}  // namespace warpcheck::chi2
