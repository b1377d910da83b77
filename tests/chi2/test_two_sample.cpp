// Two-sample tests (chi2/two_sample.h): the statistics against values computed
// by hand from the papers' formulas, and their behaviour on seeded samples
// (a correct pair passes at the rate its level says, a tilted one fails).
//
// Reference values: Python 3.11 with NumPy, Scholz and Stephens' equation 7
// (A^2_akN) and their variance written out term by term, a loop over every
// distinct value and every sample (independent of the merge the library does);
// the homogeneity statistic as the textbook contingency-table sum
// sum (O - E)^2 / E over both rows.
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "chi2/two_sample.h"
#include "sampling/pcg32.h"

namespace warpcheck::chi2 {
namespace {

TEST(AndersonDarlingTwoSample, MatchesTheFormulaWithTies) {
    const std::vector<double> a = {0.1, 0.5, 0.5, 0.9, 1.3, 2.0, 2.0, 2.0};
    const std::vector<double> b = {0.3, 0.5, 1.1, 2.0, 2.5, 3.0, 3.5};
    const AndersonDarlingTwoSample r = anderson_darling_two_sample(a, b);
    EXPECT_NEAR(r.a2, 1.1851206872123108, 1e-12);
    EXPECT_NEAR(r.standardized, 0.27372190175457717, 1e-10);
    EXPECT_EQ(r.distinct, 10u);
    // Symmetric in the two samples.
    EXPECT_NEAR(anderson_darling_two_sample(b, a).a2, r.a2, 1e-12);
}

TEST(AndersonDarlingTwoSample, MatchesTheFormulaWithoutTies) {
    const std::vector<double> a = {1, 2, 3, 4, 5, 6}, b = {7, 8, 9, 10};
    const AndersonDarlingTwoSample r = anderson_darling_two_sample(a, b);
    EXPECT_NEAR(r.a2, 3.93614282959309, 1e-12);
    EXPECT_NEAR(r.standardized, 4.60557706037647, 1e-10);
    EXPECT_LT(r.p_value, 0.02);
}

TEST(AndersonDarlingTwoSample, NanAndTooFewValuesGiveNan) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(std::isnan(anderson_darling_two_sample(std::vector<double>{1, nan, 3}, std::vector<double>{2, 4}).p_value));
    EXPECT_TRUE(std::isnan(anderson_darling_two_sample(std::vector<double>{1}, std::vector<double>{2, 3}).p_value));
    EXPECT_TRUE(std::isnan(anderson_darling_two_sample(std::vector<double>{}, std::vector<double>{2, 3, 4, 5}).a2));
}

TEST(HomogeneityTest, MatchesTheContingencyTable) {
    const std::vector<uint64_t> a = {30, 45, 25, 50}, b = {20, 60, 30, 40};
    const HomogeneityResult r = homogeneity_test(a, b);
    EXPECT_NEAR(r.statistic, 5.708513708513708, 1e-12);
    EXPECT_EQ(r.dof, 3);
    EXPECT_EQ(r.p_value, chi_square_upper_tail(r.statistic, 3));
    EXPECT_NEAR(r.effective_samples, 150.0 * 150.0 / 300.0, 1e-12);
}

TEST(HomogeneityTest, SmallCellsAreMergedNeverDropped) {
    // The smaller sample expects 2.5 in each of the first two cells: they merge.
    const std::vector<uint64_t> a = {2, 3, 500, 495}, b = {3, 2, 480, 515};
    const HomogeneityResult r = homogeneity_test(a, b);
    EXPECT_EQ(r.terms, 3u);
    EXPECT_EQ(r.merged_cells, 1u);
    EXPECT_EQ(r.dof, 2);
    // An empty sample has nothing to compare: NaN, which fails.
    EXPECT_TRUE(std::isnan(homogeneity_test(std::vector<uint64_t>{0, 0}, std::vector<uint64_t>{3, 4}).p_value));
}

// Seeded pairs of uniform samples through adaptive cells: a correct pair's
// p-values fall below 0.01 about 1% of the time (at most 6 of 100 here: the
// binomial tail P(X >= 6) at p = 0.01 is 5e-4), and a density tilted by 20%
// in one coordinate fails every time (noncentrality ~130 at these sizes).
struct Pair {
    std::vector<AdaptiveCells::Point> a, b;
};

Pair draw_pair(uint64_t seed, double tilt, std::size_t n) {
    Pcg32 rng(seed, 7);
    Pair p;
    // Density 1 + tilt (2x - 1) on [0,1], by inversion of its CDF x + tilt (x^2 - x).
    auto tilted = [&](double u) {
        if (tilt == 0.0) return u;
        const double c = 1.0 - tilt;
        return (-c + std::sqrt(c * c + 4.0 * tilt * u)) / (2.0 * tilt);
    };
    for (std::size_t i = 0; i < n; ++i) p.a.push_back({rng.next_double(), rng.next_double()});
    for (std::size_t i = 0; i < n; ++i) p.b.push_back({tilted(rng.next_double()), rng.next_double()});
    return p;
}

TEST(TwoSampleTests, CorrectPairsPassAtTheirLevelAndTiltedOnesFail) {
    int homogeneity_rejections = 0, ad_rejections = 0;
    for (uint64_t seed = 1; seed <= 100; ++seed) {
        const Pair p = draw_pair(seed, 0.0, 20000);
        const AdaptiveCells cells(p.a, p.b, 2, 8, 8);
        EXPECT_EQ(cells.cell_count(), 64u);
        homogeneity_rejections += homogeneity_test(cells.counts(p.a), cells.counts(p.b)).p_value < 0.01;
        std::vector<double> ua, ub;
        for (const auto& x : p.a) ua.push_back(x[0]);
        for (const auto& x : p.b) ub.push_back(x[0]);
        ad_rejections += anderson_darling_two_sample(ua, ub).p_value < 0.01;
    }
    EXPECT_LE(homogeneity_rejections, 6);
    EXPECT_LE(ad_rejections, 6);
    for (uint64_t seed = 1; seed <= 5; ++seed) {
        const Pair p = draw_pair(seed, 0.2, 20000);
        const AdaptiveCells cells(p.a, p.b, 2, 8, 8);
        EXPECT_LT(homogeneity_test(cells.counts(p.a), cells.counts(p.b)).p_value, 1e-4) << seed;
        std::vector<double> ua, ub;
        for (const auto& x : p.a) ua.push_back(x[0]);
        for (const auto& x : p.b) ub.push_back(x[0]);
        EXPECT_LT(anderson_darling_two_sample(ua, ub).p_value, 1e-4) << seed;
    }
}

TEST(AdaptiveCells, EqualCountsAndTiesStayTogether) {
    std::vector<AdaptiveCells::Point> a, b;
    for (int i = 0; i < 1000; ++i) a.push_back({i / 1000.0, 0.0});
    for (int i = 0; i < 1000; ++i) b.push_back({(i + 0.5) / 1000.0, 0.0});
    const AdaptiveCells line(a, b, 1, 10, 1);
    EXPECT_EQ(line.cell_count(), 10u);
    for (uint64_t c : line.counts(a)) EXPECT_EQ(c, 100u);
    // Every value tied: one cell only, whatever was asked.
    std::vector<AdaptiveCells::Point> same(50, {0.5, 0.5});
    const AdaptiveCells tied(same, same, 2, 4, 4);
    const std::vector<uint64_t> counts = tied.counts(same);
    uint64_t total = 0, nonzero = 0;
    for (uint64_t c : counts) total += c, nonzero += c > 0;
    EXPECT_EQ(total, 50u);
    EXPECT_EQ(nonzero, 1u);
}

}  // namespace
}  // namespace warpcheck::chi2
