// Marginal CDFs tabulated by cubature (chi2/marginal_cdf.h): against exact
// CDFs, for a density peaked within one strip of the uniform grid (which the
// refinement must resolve, and whose stated error must cover the true one) and
// a 2D density whose mass lies in a band narrow across the strips (which rows
// at the other marginal's quantiles must find).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "chi2/marginal_cdf.h"

namespace warpcheck::chi2 {
namespace {

constexpr int kStrips = 1024;
constexpr double kTarget = 3e-5;  // 0.03 / sqrt(10^6), as the unbinned check asks

QuadratureOptions quadrature() {
    QuadratureOptions q;
    q.accuracy_fraction = 1e-3;
    return q;
}

/// c exp(-c x) / (1 - exp(-c)) on [0, 1]: the peak at 0 is 1/c = 5e-4 wide,
/// half a strip of 1024.
constexpr double kRate = 2000.0;
double exact_cdf(double x) { return -std::expm1(-kRate * x) / -std::expm1(-kRate); }
const BatchPdf steep_exponential = [](std::span<const DomainPoint> p, std::span<double> f) {
    for (std::size_t i = 0; i < p.size(); ++i) f[i] = kRate * std::exp(-kRate * p[i][0]) / -std::expm1(-kRate);
};

double max_error(const MarginalCdf& m) {
    double worst = 0.0;
    for (int k = 0; k <= 200000; ++k) {
        const double x = std::pow(k / 200000.0, 3.0);  // dense near the peak
        worst = std::max(worst, std::abs(m(x) - exact_cdf(x)));
    }
    return worst;
}

TEST(MarginalCdf, RefinementResolvesAPeakWithinOneStripAndStatesItsError) {
    const Binning strips = strip_binning(Domain::interval(0.0, 1.0), 0, kStrips);
    const MarginalCdf coarse = tabulate_marginal_cdf(strips, 0, steep_exponential, quadrature());
    CdfRefinement r;
    r.interpolation_target = kTarget;
    r.max_strips = 8 * kStrips;
    const MarginalCdf fine = tabulate_marginal_cdf(strips, 0, steep_exponential, quadrature(), serial_for, r);
    std::printf("uniform strips: true error %.2g, stated %.2g; refined (+%zu strips): true %.2g, stated %.2g\n",
                max_error(coarse), coarse.error_bound(), fine.refined_strips, max_error(fine), fine.error_bound());
    EXPECT_GT(max_error(coarse), 1e-3);  // the uniform grid alone cannot tabulate it
    EXPECT_GT(fine.refined_strips, 0u);
    EXPECT_LE(fine.refined_strips, 7u * kStrips);
    EXPECT_LE(fine.interpolation_error, kTarget);
    EXPECT_LE(max_error(fine), fine.error_bound());  // the stated error covers the true one
    EXPECT_LE(fine.error_bound(), 1e-4);
    for (double x = 0.0; x < 1.0; x += 1e-5) EXPECT_LE(fine(x), fine(x + 1e-5)) << x;  // monotone
}

TEST(MarginalCdf, RefinementStopsAtItsBudget) {
    const Binning strips = strip_binning(Domain::interval(0.0, 1.0), 0, kStrips);
    CdfRefinement r;
    r.interpolation_target = 1e-12;
    r.max_strips = kStrips + 64;
    const MarginalCdf m = tabulate_marginal_cdf(strips, 0, steep_exponential, quadrature(), serial_for, r);
    EXPECT_EQ(m.edges.size(), kStrips + 64 + 1u);
    EXPECT_GT(m.interpolation_error, 1e-12);  // stated, not hidden
}

/// On the unit square: uniform in x, a Gaussian band of width 2e-4 in y at
/// y = 0.6180339887 (normalised over [0, 1] to well below 1e-12).
constexpr double kBand = 2e-4, kCentre = 0.6180339887;
const BatchPdf narrow_band = [](std::span<const DomainPoint> p, std::span<double> f) {
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double z = (p[i][1] - kCentre) / kBand;
        f[i] = std::exp(-0.5 * z * z) / (kBand * std::sqrt(2.0 * M_PI));
    }
};

TEST(MarginalCdf, RowsAtTheOtherMarginalsQuantilesFindANarrowBand) {
    const Domain square = Domain::unit_square();
    CdfRefinement r;
    r.interpolation_target = kTarget;
    r.max_strips = 8 * kStrips;
    const MarginalCdf y = tabulate_marginal_cdf(strip_binning(square, 1, kStrips), 1, narrow_band, quadrature(),
                                                serial_for, r);
    const Binning x_strips = strip_binning(square, 0, kStrips);
    const MarginalCdf whole = tabulate_marginal_cdf(x_strips, 0, narrow_band, quadrature(), serial_for, r);
    r.cross_cuts = quantile_cuts(y, 16);
    const MarginalCdf rows = tabulate_marginal_cdf(x_strips, 0, narrow_band, quadrature(), serial_for, r);
    std::printf("x strips over the whole y range: total %.9f; in 16 rows at y's quantiles: %.9f (y's own %.9f)\n",
                whole.total, rows.total, y.total);
    ASSERT_EQ(r.cross_cuts.size(), 15u + 2u * 5u);  // k / 16 and 1e-6 .. 1e-2 from each end
    EXPECT_NEAR(r.cross_cuts[5 + 7], kCentre, kBand);  // the median cut sits on the band
    EXPECT_NEAR(y.total, 1.0, 1e-6);
    EXPECT_NEAR(rows.total, 1.0, 1e-6);
    EXPECT_NEAR(rows(0.25), 0.25, 1e-6);
}

}  // namespace
}  // namespace warpcheck::chi2
namespace warpcheck::chi2 {
namespace {

/// 1.9 and 0.1 in turn on `bins` equal bins of [0, 1] (normalised for an even count).
BatchPdf alternating(int bins) {
    return [bins](std::span<const DomainPoint> p, std::span<double> f) {
        for (std::size_t i = 0; i < p.size(); ++i) f[i] = static_cast<long>(p[i][0] * bins) % 2 == 0 ? 1.9 : 0.1;
    };
}
double alternating_cdf(int bins, double x) {
    const double k = std::floor(x * bins), start = k / bins;
    const double pairs = std::floor(k / 2.0) * 2.0 / bins;
    return static_cast<long>(k) % 2 == 1 ? pairs + 1.9 / bins + 0.1 * (x - start) : pairs + 1.9 * (x - start);
}

TEST(MarginalCdf, ProbesMeasureStructureWithinStripsThatStripPairsCannotSee) {
    // 2 to 8 bins per strip: every strip holds the same mass, so the pair
    // estimate is 0, while the CDF's true error is up to 4.4e-4. The probes
    // inside the strips see it, and the stated error covers the true one.
    for (int bins : {2048, 3072, 4096, 6144, 8192}) {
        CdfRefinement r;
        r.interpolation_target = kTarget;
        r.max_strips = 8 * kStrips;
        const MarginalCdf m = tabulate_marginal_cdf(strip_binning(Domain::interval(0.0, 1.0), 0, kStrips), 0,
                                                    alternating(bins), quadrature(), serial_for, r);
        double worst = 0.0;
        for (int k = 0; k <= 1'000'000; ++k)
            worst = std::max(worst, std::abs(m(k * 1e-6) - alternating_cdf(bins, k * 1e-6)));
        std::printf("%d bins: true error %.3g, probes saw %.3g, stated %.3g\n", bins, worst,
                    m.probed_interpolation_error, m.error_bound());
        EXPECT_LE(worst, m.error_bound()) << bins;
        EXPECT_GE(m.probed_interpolation_error, 0.75 * worst) << bins;
        if (bins == 2048) {
            EXPECT_GT(worst, 4e-4);
            EXPECT_EQ(m.interpolation_error, kProbeMargin * m.probed_interpolation_error);  // the probes decided
        }
    }
}

/// The CDF interpolated in the strip found by a search of every edge: what
/// operator() must give, however it finds the strip.
double by_full_search(const MarginalCdf& m, double t) {
    if (!(t > m.edges.front())) return 0.0;
    if (!(t < m.edges.back())) return 1.0;
    const std::size_t j = static_cast<std::size_t>(std::upper_bound(m.edges.begin(), m.edges.end(), t) -
                                                   m.edges.begin()) - 1;
    const double w = (t - m.edges[j]) / (m.edges[j + 1] - m.edges[j]);
    return m.cdf[j] + w * (m.cdf[j + 1] - m.cdf[j]);
}

TEST(MarginalCdf, IndexedLookupsFindTheStripThatASearchOfEveryEdgeFinds) {
    // The refined peak puts hundreds of strips into a few of the index's
    // buckets; every edge, its float neighbours and the midpoints are looked up.
    CdfRefinement r;
    r.interpolation_target = kTarget;
    r.max_strips = 8 * kStrips;
    const MarginalCdf m = tabulate_marginal_cdf(strip_binning(Domain::interval(0.0, 1.0), 0, kStrips), 0,
                                                steep_exponential, quadrature(), serial_for, r);
    ASSERT_GT(m.refined_strips, 100u);
    std::size_t looked_up = 0;
    for (std::size_t j = 0; j < m.edges.size(); ++j)
        for (double t : {m.edges[j], std::nextafter(m.edges[j], -1.0), std::nextafter(m.edges[j], 2.0),
                         j + 1 < m.edges.size() ? 0.5 * (m.edges[j] + m.edges[j + 1]) : 2.0}) {
            ASSERT_EQ(m(t), by_full_search(m, t)) << t;
            const MarginalCdf::AtBand b = m.at_band(t - 1e-4, t, t + 1e-4);
            ASSERT_EQ(b.lo, by_full_search(m, t - 1e-4)) << t;
            ASSERT_EQ(b.value, by_full_search(m, t)) << t;
            ASSERT_EQ(b.hi, by_full_search(m, t + 1e-4)) << t;
            ++looked_up;
        }
    EXPECT_EQ(looked_up, 4 * m.edges.size());
}

}  // namespace
}  // namespace warpcheck::chi2
