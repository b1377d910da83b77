// The triangle domain (chi2/domain_kinds.h, Triangle): its area, membership
// with the domain's slack, boundary, the binning map (s, t) -> point and its
// inverse, equal-area cells, and the quadrature over them.
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "chi2/binning.h"
#include "chi2/quadrature.h"
#include "sampling/pcg32.h"

namespace warpcheck::chi2 {
namespace {

struct TriangleCase {
    std::string name;
    std::array<double, 2> a, b, c;
};

// Counter-clockwise, clockwise, a thin sliver, and one far from the origin.
std::vector<TriangleCase> triangles() {
    return {{"lower_left_half", {0, 0}, {1, 0}, {0, 1}},
            {"clockwise", {0.2, 0.9}, {0.9, 0.6}, {0.1, 0.1}},
            {"sliver", {-1, 0}, {3, 0.01}, {2, 0.2}},
            {"far_away", {100, 50}, {101.5, 50}, {100.5, 52}}};
}

class TriangleTest : public ::testing::TestWithParam<TriangleCase> {
protected:
    Domain domain() const { return Domain::triangle(GetParam().a, GetParam().b, GetParam().c); }
    const Triangle& kind() const { return domain_.as<Triangle>(); }
    /// A uniform point of the triangle (by reflection of the parallelogram).
    DomainPoint uniform_point(Pcg32& rng) const {
        double x = rng.next_double(), y = rng.next_double();
        if (x + y > 1) x = 1 - x, y = 1 - y;
        const auto& [a, b, c] = std::array{GetParam().a, GetParam().b, GetParam().c};
        return {a[0] + x * (b[0] - a[0]) + y * (c[0] - a[0]), a[1] + x * (b[1] - a[1]) + y * (c[1] - a[1]), 0};
    }
    Domain domain_ = domain();
};

TEST_P(TriangleTest, AreaIsHalfTheCrossProduct) {
    const auto& [_, a, b, c] = GetParam();
    const double area = 0.5 * std::abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    EXPECT_DOUBLE_EQ(domain_.measure(), area);
    EXPECT_EQ(domain_.point_dimension(), 2);
    EXPECT_FALSE(domain_.azimuthal());
    EXPECT_NE(domain_.describe().find("triangle"), std::string::npos);
}

TEST_P(TriangleTest, MembershipWithTheDomainsSlack) {
    const auto& [_, a, b, c] = GetParam();
    const Domain::Slack s = domain_.slack();
    // The vertices, the edges' midpoints and the centroid lie inside.
    for (const auto& v : {a, b, c}) EXPECT_TRUE(domain_.contains({v[0], v[1], 0}));
    const DomainPoint centroid{(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, 0};
    EXPECT_TRUE(domain_.contains(centroid));
    // Beyond the vertex a, away from the centroid: inside within a tenth of the
    // slack, outside at ten times it (along the direction the slack is widest).
    const double dx = a[0] - centroid[0], dy = a[1] - centroid[1], len = std::hypot(dx, dy);
    const double slack = std::min(s.x, s.y);
    EXPECT_TRUE(domain_.contains({a[0] + 0.1 * slack * dx / len, a[1] + 0.1 * slack * dy / len, 0}));
    EXPECT_FALSE(domain_.contains({a[0] + 10 * std::max(s.x, s.y) * dx / len,
                                   a[1] + 10 * std::max(s.x, s.y) * dy / len, 0}));
    // Across the middle of the edge bc, the same.
    const DomainPoint mid{(b[0] + c[0]) / 2, (b[1] + c[1]) / 2, 0};
    const double mx = mid[0] - centroid[0], my = mid[1] - centroid[1], ml = std::hypot(mx, my);
    EXPECT_TRUE(domain_.contains({mid[0] + 0.1 * slack * mx / ml, mid[1] + 0.1 * slack * my / ml, 0}));
    EXPECT_FALSE(domain_.contains({mid[0] + 0.5 * ml * mx / ml, mid[1] + 0.5 * ml * my / ml, 0}));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(domain_.contains({nan, centroid[1], 0}));
    EXPECT_FALSE(domain_.contains({centroid[0], nan, 0}));
}

TEST_P(TriangleTest, VerticesAreOnTheBoundaryAndTheCentroidIsNot) {
    const auto& [_, a, b, c] = GetParam();
    for (const auto& v : {a, b, c}) EXPECT_TRUE(domain_.on_boundary({v[0], v[1], 0}));
    EXPECT_FALSE(domain_.on_boundary({(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, 0}));
}

TEST_P(TriangleTest, ParametersOfInvertsPointAt) {
    const Binning binning(domain_);
    Pcg32 rng(5, 9);
    const double scale = std::max({std::abs(GetParam().a[0]), std::abs(GetParam().a[1]), 1.0});
    for (int k = 0; k < 20000; ++k) {
        const double s = rng.next_double(), t = rng.next_double();
        const DomainPoint p = binning.point_at(s, t);
        EXPECT_TRUE(domain_.contains(p)) << s << " " << t;
        const auto st = binning.parameters_of(p);
        // Cancellation in the barycentric coordinates: relative to the coordinates' size.
        EXPECT_NEAR(st[0], s, 1e-12 * scale * scale / domain_.measure()) << k;
        if (s > 1e-6) {
            EXPECT_NEAR(st[1], t, 1e-9 * scale * scale / domain_.measure()) << k;
        }
    }
    // The parameter rectangle's corners are the vertices: s = 0 is a; s = 1 is b (t = 0) and c (t = 1).
    const auto close = [](const DomainPoint& p, const std::array<double, 2>& v) {
        return std::abs(p[0] - v[0]) <= 1e-12 * std::max(1.0, std::abs(v[0])) &&
               std::abs(p[1] - v[1]) <= 1e-12 * std::max(1.0, std::abs(v[1]));
    };
    EXPECT_TRUE(close(binning.point_at(0, 0.3), GetParam().a));
    EXPECT_TRUE(close(binning.point_at(1, 0), GetParam().b));
    EXPECT_TRUE(close(binning.point_at(1, 1), GetParam().c));
}

TEST_P(TriangleTest, CellsHaveEqualAreasThatSumToTheTriangles) {
    const Binning binning(domain_, {13, 7, 0.0});
    double sum = 0.0;
    for (std::size_t cell = 0; cell < binning.cell_count(); ++cell) {
        EXPECT_NEAR(binning.cell_measure(cell), domain_.measure() / 91.0, 1e-14 * domain_.measure()) << cell;
        sum += binning.cell_measure(cell);
    }
    EXPECT_NEAR(sum, domain_.measure(), 1e-12 * domain_.measure());
}

// Uniform points fill the equal-area cells evenly (a chi-square well within
// its 1e-6 quantile), and the fast binning agrees with cell_of point by point.
TEST_P(TriangleTest, UniformPointsFillTheCellsEvenlyAndBinLikeCellOf) {
    const Binning binning(domain_, {8, 8, 0.0});
    Pcg32 rng(3, 17);
    constexpr int kPoints = 64000;
    std::vector<std::array<float, 3>> points;
    std::vector<uint64_t> exact(binning.cell_count(), 0);
    for (int k = 0; k < kPoints; ++k) {
        const DomainPoint p = uniform_point(rng);
        const std::array<float, 3> f{static_cast<float>(p[0]), static_cast<float>(p[1]), 0.0f};
        points.push_back(f);
        const std::ptrdiff_t cell = binning.cell_of({f[0], f[1], 0.0});
        ASSERT_GE(cell, 0) << k;
        ++exact[static_cast<std::size_t>(cell)];
    }
    Histogram fast;
    fast.counts.assign(binning.cell_count(), 0);
    binning.bin(std::span<const std::array<float, 3>>(points), fast);
    EXPECT_EQ(fast.counts, exact);
    EXPECT_EQ(fast.outside, 0u);
    const double expected = kPoints / 64.0;
    double chi2 = 0.0;
    for (uint64_t n : exact) {
        const double d = static_cast<double>(n) - expected;
        chi2 += d * d / expected;
    }
    EXPECT_LT(chi2, 140.0);  // 63 dof: the 1e-6 upper quantile is about 131
}

TEST_P(TriangleTest, QuadratureOfAUniformDensityGivesEveryCellItsShare) {
    const Binning binning(domain_, {8, 8, 0.0});
    const double density = 1.0 / domain_.measure();
    const BatchPdf pdf = [density](std::span<const DomainPoint>, std::span<double> out) {
        for (double& d : out) d = density;
    };
    const CellIntegrals in = integrate_cells(binning, pdf, {});
    EXPECT_NEAR(in.total, 1.0, 1e-12);
    for (double p : in.probability) EXPECT_NEAR(p, 1.0 / 64.0, 1e-13);
}

INSTANTIATE_TEST_SUITE_P(Triangles, TriangleTest, ::testing::ValuesIn(triangles()),
                         [](const ::testing::TestParamInfo<TriangleCase>& p) { return p.param.name; });

TEST(Triangle, EdgesOfTheUnitHalfSquareAreItsBoundary) {
    const Domain d = Domain::triangle({0, 0}, {1, 0}, {0, 1});
    EXPECT_TRUE(d.on_boundary({0.25, 0.75, 0}));   // the hypotenuse, exactly
    EXPECT_TRUE(d.on_boundary({0.0, 0.4, 0}));
    EXPECT_TRUE(d.on_boundary({0.3, 0.0, 0}));
    EXPECT_FALSE(d.on_boundary({0.25, 0.5, 0}));
    EXPECT_FALSE(d.on_boundary({0.5, 0.5 + 0x1p-24, 0}));  // just outside
    EXPECT_DOUBLE_EQ(d.measure(), 0.5);
}

TEST(Triangle, DegenerateOrNonFiniteVerticesAreRefused) {
    EXPECT_THROW(Domain::triangle({0, 0}, {1, 1}, {2, 2}), std::invalid_argument);
    EXPECT_THROW(Domain::triangle({0, 0}, {0, 0}, {0, 1}), std::invalid_argument);
    EXPECT_THROW(Domain::triangle({0, 0}, {1, 0}, {0, std::nan("")}), std::invalid_argument);
    EXPECT_THROW(Domain::triangle({0, 0}, {1, 0}, {0, std::numeric_limits<double>::infinity()}),
                 std::invalid_argument);
}

}  // namespace
}  // namespace warpcheck::chi2
