// Each domain's binning: the cells cover the domain, their measures add up to
// the domain's measure, and the fast classifier agrees with the exact one.
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "chi2/binning.h"
#include "sampling/pcg32.h"

namespace warpcheck::chi2 {
namespace {

struct DomainCase {
    std::string name;
    Domain domain;
    BinResolution resolution;
};

std::vector<DomainCase> domain_cases() {
    return {
        {"interval", Domain::interval(-2.0, 3.0), {}},
        {"interval_coarse", Domain::interval(0.0, 1.0), {7, 0, 1.0}},
        {"half_line", Domain::half_line(1.0), {}},
        {"half_line_scaled", Domain::half_line(0.0), {50, 0, 0.01}},
        {"box", Domain::box(-1.0, 2.0, 0.5, 1.5), {}},
        {"box_uneven", Domain::unit_square(), {13, 5, 1.0}},
        {"disk", Domain::unit_disk(), {}},
        {"sphere", Domain::sphere(), {}},
        {"hemisphere", Domain::hemisphere(), {}},
        {"cone_cap", Domain::spherical_cap(0.7), {24, 9, 1.0}},
        {"sphere_odd_columns", Domain::sphere(), {20, 10, 1.0}},  // phi by fast atan2, not the octant table
        {"disk_odd_columns", Domain::unit_disk(), {13, 7, 1.0}},
        {"lower_half_line", Domain::lower_half_line(-1.0), {}},
        {"lower_half_line_scaled", Domain::lower_half_line(2.0), {50, 0, 0.01}},
        {"real_line", Domain::real_line(), {}},
        {"real_line_centred", Domain::real_line(), {51, 0, 0.5, 40.0}},
    };
}

class BinningTest : public ::testing::TestWithParam<DomainCase> {};

/// A random point of the domain (not uniformly distributed; coverage only).
DomainPoint random_point(const Domain& d, Pcg32& rng) {
    const double u = rng.next_double(), v = rng.next_double();
    if (const auto* i = std::get_if<Interval>(&d.shape())) return {i->a + (i->b - i->a) * u, 0, 0};
    if (const auto* h = std::get_if<HalfLine>(&d.shape())) return {h->a - std::log1p(-u) * 3.0, 0, 0};
    if (const auto* l = std::get_if<LowerHalfLine>(&d.shape())) return {l->b + std::log1p(-u) * 3.0, 0, 0};
    if (d.is<RealLine>()) return {40.0 + std::tan(std::numbers::pi * (u - 0.5)), 0, 0};  // Cauchy: both tails
    if (const auto* b = std::get_if<Box>(&d.shape()))
        return {b->x0 + (b->x1 - b->x0) * u, b->y0 + (b->y1 - b->y0) * v, 0};
    const double phi = 2 * std::numbers::pi * v;
    if (d.is<Disk>()) return {std::sqrt(u) * std::cos(phi), std::sqrt(u) * std::sin(phi), 0};
    const double z_min = d.as<SphericalCap>().z_min, z = z_min + (1 - z_min) * u, s = std::sqrt(1 - z * z);
    return {s * std::cos(phi), s * std::sin(phi), z};
}

TEST_P(BinningTest, CellMeasuresSumToDomainMeasure) {
    const Binning b(GetParam().domain, GetParam().resolution);
    ASSERT_GT(b.cell_count(), 1u);
    double sum = 0.0;
    for (std::size_t c = 0; c < b.cell_count(); ++c) {
        const double m = b.cell_measure(c);
        EXPECT_GT(m, 0.0) << c;
        sum += m;
    }
    if (b.domain().is<LowerHalfLine>() || b.domain().is<RealLine>()) {
        // A tail cell at each infinite end; the finite cells span the rest.
        EXPECT_TRUE(std::isinf(b.cell_measure(0)));
        const bool both = b.domain().is<RealLine>();
        const std::size_t last = b.cell_count() - 1;
        EXPECT_EQ(std::isinf(b.cell_measure(last)), both);
        double finite = 0.0;
        for (std::size_t c = 1; c < (both ? last : b.cell_count()); ++c) finite += b.cell_measure(c);
        const double start = b.point_at(b.cell_rect(1).u0, 0.5)[0];
        const double end = both ? b.point_at(b.cell_rect(last).u0, 0.5)[0] : b.domain().b();
        EXPECT_NEAR(finite, end - start, 1e-9 * std::abs(end - start));
    } else if (b.domain().is<HalfLine>()) {
        // Finite cells end where the tail cell starts; the tail is infinite.
        const std::size_t tail = b.cell_count() - 1;
        EXPECT_TRUE(std::isinf(b.cell_measure(tail)));
        double finite = 0.0;
        for (std::size_t c = 0; c < tail; ++c) finite += b.cell_measure(c);
        const double tail_start = b.point_at(b.cell_rect(tail).u0, 0.5)[0];
        EXPECT_NEAR(finite, tail_start - b.domain().a(), 1e-9 * tail_start);
    } else {
        EXPECT_NEAR(sum, b.domain().measure(), 1e-12 * b.domain().measure());
    }
}

TEST_P(BinningTest, CellsTileTheParameterRange) {
    const Binning b(GetParam().domain, GetParam().resolution);
    const ParamRect all = b.parameter_bounds();
    double area = 0.0;
    for (std::size_t c = 0; c < b.cell_count(); ++c) {
        const ParamRect r = b.cell_rect(c);
        EXPECT_GE(r.u0, all.u0);
        EXPECT_LE(r.u1, all.u1);
        EXPECT_GE(r.v0, all.v0);
        EXPECT_LE(r.v1, all.v1);
        area += (r.u1 - r.u0) * (r.v1 - r.v0);
        // Neighbours share edges exactly: no gaps, no overlaps.
        const std::size_t col = c % static_cast<std::size_t>(b.cols());
        if (col + 1 < static_cast<std::size_t>(b.cols())) {
            EXPECT_EQ(r.u1, b.cell_rect(c + 1).u0);
        }
        if (c + static_cast<std::size_t>(b.cols()) < b.cell_count()) {
            EXPECT_EQ(r.v1, b.cell_rect(c + static_cast<std::size_t>(b.cols())).v0);
        }
    }
    EXPECT_NEAR(area, (all.u1 - all.u0) * (all.v1 - all.v0), 1e-12 * (all.u1 - all.u0) * (all.v1 - all.v0));
}

TEST_P(BinningTest, EveryPointOfTheDomainFallsInTheCellThatContainsIt) {
    const Binning b(GetParam().domain, GetParam().resolution);
    Pcg32 rng(7, 11);
    for (int k = 0; k < 20000; ++k) {
        const DomainPoint p = random_point(b.domain(), rng);
        const std::ptrdiff_t cell = b.cell_of(p);
        ASSERT_GE(cell, 0) << k;
        const ParamRect r = b.cell_rect(static_cast<std::size_t>(cell));
        const auto uv = b.parameters_of(p);
        const double slack = 1e-12;
        EXPECT_TRUE(uv[0] >= r.u0 - slack && uv[0] <= r.u1 + slack) << k;
        if (b.parameter_dimension() == 2) {
            EXPECT_TRUE(uv[1] >= r.v0 - slack && uv[1] <= r.v1 + slack) << k;
        }
    }
}

TEST_P(BinningTest, CellCentresMapBackToTheirCell) {
    const Binning b(GetParam().domain, GetParam().resolution);
    for (std::size_t c = 0; c < b.cell_count(); ++c) {
        const ParamRect r = b.cell_rect(c);
        const double u = 0.5 * (r.u0 + r.u1), v = 0.5 * (r.v0 + r.v1);
        EXPECT_EQ(b.cell_of(b.point_at(u, v)), static_cast<std::ptrdiff_t>(c)) << c;
    }
}

/// The cubature weights each column of its nodes by one Jacobian
/// (chi2/quadrature.cpp): a kind's may not depend on v.
TEST_P(BinningTest, JacobianDependsOnUAlone) {
    const Binning b(GetParam().domain, GetParam().resolution);
    const ParamRect all = b.parameter_bounds();
    for (double fu : {0.01, 0.3, 0.77, 0.99}) {
        const double u = all.u0 + fu * (all.u1 - all.u0);
        const double j = b.jacobian(u, all.v0 + 0.5 * (all.v1 - all.v0));
        for (double fv : {0.0, 0.01, 0.4, 0.93, 1.0}) EXPECT_EQ(b.jacobian(u, all.v0 + fv * (all.v1 - all.v0)), j);
    }
}

TEST_P(BinningTest, FastBinningAgreesWithExactClassification) {
    const Binning b(GetParam().domain, GetParam().resolution);
    Pcg32 rng(3, 5);
    std::vector<std::array<float, 3>> points;
    Histogram expected;
    expected.counts.assign(b.cell_count(), 0);
    for (int k = 0; k < 50000; ++k) {
        const DomainPoint p = random_point(b.domain(), rng);
        const std::array<float, 3> f = {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
        points.push_back(f);
        const std::ptrdiff_t cell = b.cell_of({f[0], f[1], f[2]});
        ASSERT_GE(cell, 0);
        ++expected.counts[static_cast<std::size_t>(cell)];
    }
    Histogram fast;
    fast.counts.assign(b.cell_count(), 0);
    b.bin(std::span<const std::array<float, 3>>(points), fast);
    EXPECT_EQ(fast.outside, 0u);
    EXPECT_EQ(fast.nan, 0u);
    EXPECT_EQ(fast.counts, expected.counts);
}

TEST_P(BinningTest, NaNAndOutsideSamplesAreCountedApart) {
    const Binning b(GetParam().domain, GetParam().resolution);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    // Far outside: below every domain but (-inf, b], above that; the real line has only infinities outside.
    const bool real_line = b.domain().is<RealLine>();
    const float far = b.domain().is<LowerHalfLine>() ? 1e6f : real_line ? -inf : -1e6f;
    std::vector<std::array<float, 3>> points = {{nan, 0, 0}, {nan, nan, nan}, {inf, inf, inf}, {far, far, far}};
    Histogram h;
    h.counts.assign(b.cell_count(), 0);
    b.bin(std::span<const std::array<float, 3>>(points), h);
    EXPECT_EQ(h.nan, 2u);
    EXPECT_EQ(h.outside, 2u);
    EXPECT_EQ(h.total(), 4u);
    EXPECT_EQ(b.cell_of({std::nan(""), 0, 0}), Binning::kNaN);
    EXPECT_EQ(b.cell_of({far, far, far}), Binning::kOutside);
    if (real_line) {
        EXPECT_GE(b.cell_of({-1e30, 0, 0}), 0);
    }
}

INSTANTIATE_TEST_SUITE_P(Domains, BinningTest, ::testing::ValuesIn(domain_cases()),
                         [](const ::testing::TestParamInfo<DomainCase>& param_info) { return param_info.param.name; });

TEST(Binning, DefaultResolutions) {
    EXPECT_EQ(Binning(Domain::interval(0, 1)).cell_count(), 200u);
    EXPECT_EQ(Binning(Domain::hemisphere()).cols(), 32);
    EXPECT_EQ(Binning(Domain::hemisphere()).rows(), 32);
    EXPECT_EQ(Binning(Domain::unit_disk()).cell_count(), 1024u);
    EXPECT_EQ(Binning(Domain::unit_square()).cell_count(), 1024u);
}

TEST(Binning, SphericalCellAreaIsSolidAngle) {
    // A cell of the (phi, cos theta) grid: dphi * dz steradians, no Jacobian.
    const Binning b(Domain::sphere(), {8, 4, 1.0});
    for (std::size_t c = 0; c < b.cell_count(); ++c)
        EXPECT_NEAR(b.cell_measure(c), 4 * std::numbers::pi / 32, 1e-15);
}

TEST(Binning, ToleranceAtTheBoundary) {
    const Binning hemi(Domain::hemisphere());
    // Slightly below the horizon (rounding): the bottom row. Far below: outside.
    EXPECT_GE(hemi.cell_of({1.0, 0.0, -1e-7}), 0);
    EXPECT_LT(hemi.cell_of({1.0, 0.0, -1e-7}), hemi.cols());
    EXPECT_EQ(hemi.cell_of({0.9, 0.0, -0.1}), Binning::kOutside);
    // Not unit length.
    EXPECT_EQ(hemi.cell_of({0.0, 0.0, 1.01}), Binning::kOutside);
    EXPECT_GE(hemi.cell_of({0.0, 0.0, 1.000001}), 0);
    const Binning line(Domain::interval(0, 1));
    EXPECT_EQ(line.cell_of({1.0 + 1e-7, 0, 0}), 199);
    EXPECT_EQ(line.cell_of({1.001, 0, 0}), Binning::kOutside);
    const Binning half(Domain::half_line(0));
    EXPECT_EQ(half.cell_of({std::numeric_limits<double>::infinity(), 0, 0}), Binning::kOutside);
    EXPECT_EQ(half.cell_of({1e300, 0, 0}), 199);  // the tail cell
}

TEST(Binning, ZeroCellHitsWithinToleranceAreSnapped) {
    // Density zero below the equator of a sphere: a sample rounded to z = -1e-7
    // moves to the row above; one at z = -0.01 stays in its zero cell.
    const Binning b(Domain::sphere(), {4, 2, 1.0});
    std::vector<unsigned char> zero(b.cell_count(), 0);
    for (std::size_t c = 0; c < 4; ++c) zero[c] = 1;  // row 0: z in [-1, 0)
    const std::vector<std::array<float, 3>> points = {{1.0f, 0.0f, -1e-7f}, {0.99995f, 0.0f, -0.01f}};
    Histogram h;
    h.counts.assign(b.cell_count(), 0);
    b.bin(std::span<const std::array<float, 3>>(points), h, zero);
    EXPECT_EQ(h.snapped, 1u);
    EXPECT_EQ(h.counts[4], 1u);
    EXPECT_EQ(h.counts[0], 1u);
}

TEST(FastPhi, WithinThreeTimesTenToTheMinusEightOfAtan2) {
    Pcg32 rng(1, 2);
    double worst = 0.0;
    for (int k = 0; k < 200000; ++k) {
        const double x = 2 * rng.next_double() - 1, y = 2 * rng.next_double() - 1;
        double exact = std::atan2(y, x);
        if (exact < 0) exact += 2 * std::numbers::pi;
        worst = std::max(worst, std::abs(fast_phi(x, y) - exact));
    }
    EXPECT_LE(worst, 3e-8);
    EXPECT_EQ(fast_phi(0.0, 0.0), 0.0);
    EXPECT_NEAR(fast_phi(0.0, 1.0), std::numbers::pi / 2, 3e-8);
    EXPECT_NEAR(fast_phi(-1.0, 0.0), std::numbers::pi, 3e-8);
}

// Interval cells hold exactly the floats between their float-rounded edges, so a
// narrow interval (about 100 floats per cell) gets exact expected counts.
TEST(IntervalBinning, EdgesAreFloatsAndSplitTheFloatsExactly) {
    const Binning bins(Domain::interval(0.999, 1.001));
    for (std::size_t c = 1; c < bins.cell_count(); ++c) {
        const double edge = bins.cell_rect(c).u0;
        ASSERT_EQ(edge, static_cast<double>(static_cast<float>(edge))) << "edge " << c << " is not a float";
        ASSERT_EQ(edge, bins.cell_rect(c - 1).u1);
    }
    // Every float of the interval lands in the cell whose [u0, u1) holds it.
    for (float x = 0.999f; x < 1.001f; x = std::nextafter(x, 2.0f)) {
        const std::ptrdiff_t cell = bins.cell_of({x, 0, 0});
        ASSERT_GE(cell, 0);
        const ParamRect r = bins.cell_rect(static_cast<std::size_t>(cell));
        ASSERT_TRUE(x >= r.u0 && (x < r.u1 || static_cast<std::size_t>(cell) + 1 == bins.cell_count())) << x;
    }
}

}  // namespace
}  // namespace warpcheck::chi2
