// The statistics engine's model of float warps (issue 22): the verified
// quadrature bound, the density's float noise, the bands of Pearson's
// statistic, cells no narrower than the float resolution allows, and samples
// exactly at a pole. Each rule is shown where it is needed (a correct float
// input that fails without it) and where it must not excuse anything.
#include <cmath>
#include <functional>
#include <numbers>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "chi2/binning.h"
#include "chi2/pearson.h"
#include "chi2/quadrature.h"
#include "sampling/pcg32.h"
#include "tests/chi2/pointwise_pdf.h"

namespace warpcheck::chi2 {
namespace {


using test_pdfs::float_pointwise;

// Density 2 on the triangle x + y <= 1 of the unit square, tested in float as
// a renderer writes it: on the default 32 x 32 grid the jump runs through 32
// cells' corners, where the symmetric Gauss-Kronrod nodes sit exactly on it.
double triangle(const DomainPoint& p) {
    return static_cast<float>(p[0]) + static_cast<float>(p[1]) <= 1.0f ? 2.0 : 0.0;
}

TEST(VerifiedQuadrature, JumpOnTheCellDiagonalsUnderstatesAnUnverifiedBound) {
    const Binning b(Domain::unit_square());
    QuadratureOptions plain;
    const CellIntegrals q = integrate_cells(b, float_pointwise(triangle), plain);
    // Without verification the stated bound is far too small for the actual error.
    EXPECT_GT(std::abs(q.total - 1.0), 10.0 * q.error_total);
}

TEST(VerifiedQuadrature, JumpOnTheCellDiagonalsIsCoveredWhenVerified) {
    const Binning b(Domain::unit_square());
    QuadratureOptions verified;
    verified.verify = true;
    const CellIntegrals q = integrate_cells(b, float_pointwise(triangle), verified);
    EXPECT_LE(std::abs(q.total - 1.0), q.error_total);
    EXPECT_GE(q.verification_mismatches, 32u);  // the cells the diagonal cuts through their corners
    // Each cut cell's bound covers its own error: the exact mass is half or all or none of the cell.
    for (std::size_t c = 0; c < b.cell_count(); ++c) {
        const ParamRect r = b.cell_rect(c);
        const double area = (r.u1 - r.u0) * (r.v1 - r.v0);
        const double exact = r.u1 + r.v1 <= 1.0 + 1e-12 ? 2.0 * area : r.u0 + r.v0 >= 1.0 - 1e-12 ? 0.0 : area;
        EXPECT_LE(std::abs(q.probability[c] - exact), q.error[c] + 1e-12) << c;
    }
}

TEST(VerifiedQuadrature, SmoothDensitiesAreNotFlagged) {
    const Binning b(Domain::hemisphere());
    QuadratureOptions verified;
    verified.verify = true;
    const CellIntegrals q = integrate_cells(b, float_pointwise([](const DomainPoint& p) { return p[2] / std::numbers::pi; }), verified);
    EXPECT_EQ(q.verification_mismatches, 0u);
    EXPECT_NEAR(q.total, 1.0, 1e-7);
}

// Henyey-Greenstein with g = 0.99 in float: 1 + g^2 is rounded before it
// cancels against 2 g cos theta; its noise is large, a smooth density's is not.
TEST(FloatNoise, CancellingFloatDensityHasNoiseOfItsError) {
    const Binning b(Domain::sphere());
    QuadratureOptions o;
    o.float_noise = true;
    const auto hg = [](const DomainPoint& p) {
        const float g = 0.99f, c = static_cast<float>(p[2]);
        const float d = 1.0f + g * g - 2.0f * g * c;
        return static_cast<double>((1.0f - g * g) / (4.0f * std::numbers::pi_v<float> * d * std::sqrt(d)));
    };
    const CellIntegrals q = integrate_cells(b, float_pointwise(hg), o);
    ASSERT_EQ(q.float_noise.size(), b.cell_count());
    EXPECT_GT(std::abs(q.total - 1.0), 1e-5);  // the float pdf misses 1 by far more than 2^-20
    EXPECT_LT(std::abs(q.total - 1.0), q.float_noise_total);
    const CellIntegrals smooth =
        integrate_cells(b, float_pointwise([](const DomainPoint& p) { return (1.0 + p[2]) / (4.0 * std::numbers::pi); }), o);
    EXPECT_LT(smooth.float_noise_total, 1e-6);
}

// A tiny support on a big domain: evaluated at float points, a 0.25 degree
// cap's density stands for half a float step beyond its rim, 0.3% of its mass;
// the jump band bounds it.
TEST(FloatNoise, JumpBandCoversATinyCapsRim) {
    const Binning b(Domain::spherical_cap(0.99999));
    const float c = static_cast<float>(std::cos(0.25 * std::numbers::pi / 180.0));
    const double density = 1.0 / (2.0 * std::numbers::pi * (1.0 - double{c}));
    QuadratureOptions o;
    o.float_noise = true;
    const CellIntegrals q =
        integrate_cells(b, float_pointwise([&](const DomainPoint& p) { return p[2] >= c ? density : 0.0; }), o);
    EXPECT_GT(std::abs(q.total - 1.0), 1e-3);
    EXPECT_LT(std::abs(q.total - 1.0), q.float_noise_total + q.error_total);
}

// The integral is found around samples in a cell whose nodes all miss a sliver.
TEST(GuidedIntegration, FindsASliverBetweenTheNodes) {
    const Binning b(Domain::unit_square());
    const ParamRect cell = b.cell_rect(b.cell_at_parameters(0.5, 0.5));
    const double x0 = 0.5 * (cell.u0 + cell.u1) + 1e-4;  // a strip 1e-6 wide, off every node
    const auto strip = [&](const DomainPoint& p) { return p[0] >= x0 && p[0] < x0 + 1e-6 ? 1e6 : 0.0; };
    QuadratureOptions o;
    const CellIntegrals plain = integrate_rects(b, std::span<const ParamRect>(&cell, 1), float_pointwise(strip), o);
    EXPECT_EQ(plain.probability[0], 0.0);
    // The extreme samples of the many that land in the strip lie near its edges.
    const std::vector<std::array<double, 2>> at = {{x0 + 2e-8, cell.v0 + 0.01 * (cell.v1 - cell.v0)},
                                                   {x0 + 0.98e-6, cell.v1 - 0.01 * (cell.v1 - cell.v0)}};
    o.float_noise = true;
    const GuidedIntegral g = integrate_around(b, cell, at, float_pointwise(strip), o);
    const double exact = (cell.v1 - cell.v0);  // 1e6 * 1e-6 * height
    // Within its bound and the float resolution of the strip's edges (a 1e-6
    // strip is 17 floats wide at 0.5).
    EXPECT_NEAR(g.value, exact, g.error + g.float_noise);
    EXPECT_LT(g.float_noise, 0.2 * exact);
}

// Pearson with bands: expected counts off by up to `band` (within it) must not
// raise the false-rejection rate above the level, which the central
// chi-square's p-value does.
TEST(PearsonBands, KeepTheLevelWhenExpectationsAreOffWithinTheirBands) {
    constexpr int kCells = 200, kTrials = 400;
    constexpr double kN = 20000.0, kLevel = 0.05;
    std::vector<double> p_true(kCells), expected(kCells), band(kCells);
    for (int i = 0; i < kCells; ++i) {
        p_true[i] = 1.0 / kCells;
        const double e = kN / kCells;
        // The claimed expectation is off by +-0.5 sd in alternate cells; the band says so.
        expected[i] = e + (i % 2 ? 0.5 : -0.5) * std::sqrt(e);
        band[i] = 0.5 * std::sqrt(e);
    }
    Pcg32 rng(3, 4);
    int rejected_central = 0, rejected_banded = 0;
    std::vector<double> observed(kCells);
    for (int t = 0; t < kTrials; ++t) {
        std::fill(observed.begin(), observed.end(), 0.0);
        for (int s = 0; s < static_cast<int>(kN); ++s) observed[rng.next_u32() % kCells] += 1.0;
        rejected_central += pearson_test(observed, expected).p_value < kLevel;
        rejected_banded += pearson_test(observed, expected, band).p_value < kLevel;
    }
    // Noncentrality 200 * 0.25 = 50 on 199 dof: the central test rejects far more
    // than 5%; the banded one at most ~5% (binomial noise: 3 sd is 3.3%).
    EXPECT_GT(rejected_central, 2 * kLevel * kTrials);
    EXPECT_LE(rejected_banded, (kLevel + 0.033) * kTrials);
}

TEST(PearsonBands, ZeroBandsAreTheClassicalTest) {
    const std::vector<double> o = {90, 110, 105, 95}, e = {100, 100, 100, 100}, zero(4, 0.0);
    EXPECT_EQ(pearson_test(o, e, zero).p_value, pearson_test(o, e).p_value);
    EXPECT_EQ(pearson_test(o, e, zero).noncentrality, 0.0);
}

TEST(PearsonBands, AGrossDeviationStillFails) {
    std::vector<double> o(100, 1000.0), e(100, 1000.0), band(100, 0.1 * std::sqrt(1000.0));
    o[0] = 1600.0;  // a 19 sd excess in one cell
    o[1] = 400.0;
    EXPECT_LT(pearson_test(o, e, band).p_value, 1e-6);
}

// Cells no narrower than the float resolution allows: a narrow interval's
// cells are widened until a float step at each edge is within a Poisson
// deviation; ordinary domains keep their grids.
TEST(FloatAwareResolution, NarrowDomainsGetFewerCells) {
    EXPECT_LT(float_aware_resolution(Domain::interval(0.999, 1.001), {}, 1'000'000).first, 200);
    // A tiny cap's cos theta is read off x and y near the pole (issue 34), so
    // its rows keep their float resolution however thin: its grid stays whole.
    EXPECT_EQ(float_aware_resolution(Domain::spherical_cap(0.99999), {}, 1'000'000).second, 32);
    const BinResolution square = float_aware_resolution(Domain::unit_square(), {}, 1'000'000);
    EXPECT_EQ(square.first, 32);
    EXPECT_EQ(square.second, 32);
    const BinResolution sphere = float_aware_resolution(Domain::sphere(), {}, 1'000'000);
    EXPECT_EQ(sphere.first, 32);
    EXPECT_EQ(sphere.second, 32);
}

// A sample exactly at the pole has no azimuth: it is dealt out over its row.
TEST(Poles, ArePutInNoColumnAndDealtOutOverTheirRow) {
    const Binning b(Domain::sphere());
    Histogram h;
    h.counts.assign(b.cell_count(), 0);
    const std::vector<std::array<float, 3>> poles(65, {0.0f, 0.0f, 1.0f});
    b.bin(std::span<const std::array<float, 3>>(poles), h);
    ASSERT_EQ(h.poles.size(), static_cast<std::size_t>(b.rows()));
    EXPECT_EQ(h.poles.back(), 65u);
    h.spread_poles(b.cols());
    const std::size_t top = static_cast<std::size_t>(b.rows() - 1) * b.cols();
    EXPECT_EQ(h.counts[top], 3u);  // 65 = 2 * 32 + 1: the first column gets the one left over
    for (int c = 1; c < b.cols(); ++c) EXPECT_EQ(h.counts[top + c], 2u) << c;
    EXPECT_TRUE(h.poles.empty());
}

}  // namespace
}  // namespace warpcheck::chi2
