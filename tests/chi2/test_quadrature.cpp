// Expected cell probabilities: exact for polynomials, within the accuracy rule
// for a sharply peaked density with a known closed-form cell mass.
#include <atomic>
#include <cmath>
#include <functional>
#include <numbers>
#include <span>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>

#include "chi2/quadrature.h"
#include "tests/chi2/pointwise_pdf.h"

namespace warpcheck::chi2 {
namespace {


using test_pdfs::pointwise;

/// Trowbridge-Reitz (GGX) normal distribution times cos theta, a density in
/// solid angle on the hemisphere; very peaked at small alpha.
double ggx_pdf(double z, double alpha) {
    if (z <= 0) return 0.0;
    const double z2 = z * z, a2 = alpha * alpha;
    const double d = a2 * z2 + (1 - z2);
    return a2 * z / (std::numbers::pi * d * d);
}
/// Its mass with cos theta >= z: tan^2 / (alpha^2 + tan^2) at tan^2 = (1 - z^2) / z^2.
double ggx_mass_above(double z, double alpha) {
    const double s2 = 1 - z * z;
    return s2 / (alpha * alpha * z * z + s2);
}

TEST(Quadrature, UniformSphereCellsAreExact) {
    const Binning b(Domain::sphere());
    const CellIntegrals q = integrate_cells(b, pointwise([](const DomainPoint&) { return 0.25 / std::numbers::pi; }), {});
    for (std::size_t c = 0; c < b.cell_count(); ++c)
        EXPECT_NEAR(q.probability[c], b.cell_measure(c) * 0.25 / std::numbers::pi, 1e-16) << c;
    EXPECT_NEAR(q.total, 1.0, 1e-12);
    EXPECT_EQ(q.unconverged_cells, 0u);
    // One 15 x 15 rule per cell: nothing to refine for a constant.
    EXPECT_EQ(q.evaluations, b.cell_count() * 225);
}

TEST(Quadrature, CosineHemisphereMatchesClosedForm) {
    const Binning b(Domain::hemisphere());
    const CellIntegrals q = integrate_cells(b, pointwise([](const DomainPoint& p) { return p[2] / std::numbers::pi; }), {});
    for (std::size_t c = 0; c < b.cell_count(); ++c) {
        const ParamRect r = b.cell_rect(c);
        const double exact = (r.u1 - r.u0) / std::numbers::pi * 0.5 * (r.v1 * r.v1 - r.v0 * r.v0);
        EXPECT_NEAR(q.probability[c], exact, 1e-15) << c;
    }
    EXPECT_NEAR(q.total, 1.0, 1e-12);
}

TEST(Quadrature, PeakedDensityMeetsTheAccuracyRule) {
    // alpha = 0.05: nearly all mass has 1 - z < 0.01, inside the top row of cells.
    const double alpha = 0.05;
    const Binning b(Domain::hemisphere());
    QuadratureOptions opt;
    opt.sample_count = 10'000'000;
    const CellIntegrals q = integrate_cells(b, pointwise([&](const DomainPoint& p) { return ggx_pdf(p[2], alpha); }), opt);
    EXPECT_EQ(q.unconverged_cells, 0u);
    for (std::size_t c = 0; c < b.cell_count(); ++c) {
        const ParamRect r = b.cell_rect(c);
        const double exact = (r.u1 - r.u0) / (2 * std::numbers::pi) * (ggx_mass_above(r.v0, alpha) - ggx_mass_above(r.v1, alpha));
        // The rule: |error| <= 1% of the cell's Poisson deviation at N samples.
        EXPECT_TRUE(std::abs(q.probability[c] - exact) <= cell_tolerance(exact, opt))
            << c << " " << q.probability[c] << " " << exact << " " << cell_tolerance(exact, opt);
    }
    EXPECT_NEAR(q.total, 1.0, 1e-6);
}

// A support's edge inside cells: the uniform density of a cap z >= z0 whose
// rim runs through a row of cells, 0.0148 above its lower side, where the
// rule's nodes straddle a jump. Every cell within its bound of its exact
// mass (the overlap of its z-range with the cap), and no cell unconverged.
TEST(QuadratureEdges, ACapsRimInsideARowOfCellsKeepsEveryBound) {
    const Binning b(Domain::sphere());
    const double z0 = std::cos(0.7), mass = 2.0 * std::numbers::pi * (1.0 - z0);
    QuadratureOptions opt;
    opt.verify = true;
    const CellIntegrals q = integrate_cells(b, pointwise([&](const DomainPoint& p) { return p[2] >= z0 ? 1.0 / mass : 0.0; }), opt);
    EXPECT_EQ(q.unconverged_cells, 0u);
    EXPECT_EQ(q.verification_mismatches, 0u);
    for (std::size_t c = 0; c < b.cell_count(); ++c) {
        const ParamRect r = b.cell_rect(c);
        const double exact = (r.u1 - r.u0) * std::max(0.0, r.v1 - std::max(r.v0, z0)) / mass;
        EXPECT_LE(std::abs(q.probability[c] - exact), q.error[c] + 1e-15) << c << " bound " << q.error[c];
        EXPECT_LE(std::abs(q.probability[c] - exact), cell_tolerance(exact, opt)) << c;
    }
    EXPECT_NEAR(q.total, 1.0, q.error_total);
}

/// The length of [z_lo, z_hi] inside the cap around (sin a, 0, cos a) of
/// angular radius rho, on the meridian at azimuth phi: with z = cos t, the
/// meridian's point at t is inside where k sin t + cos(a) cos t >= cos rho
/// (k = cos(phi) sin a), i.e. |t - d| <= acos(cos rho / R) for
/// R = hypot(k, cos a), d = atan2(k, cos a), t in [0, pi].
double cap_overlap(double phi, double a, double rho, double z_lo, double z_hi) {
    const double k = std::cos(phi) * std::sin(a), c = std::cos(a), big_r = std::hypot(k, c);
    if (std::cos(rho) > big_r) return 0.0;
    const double d = std::atan2(k, c), w = std::acos(std::cos(rho) / big_r);
    if (d + w < 0.0 || d - w > std::numbers::pi) return 0.0;  // the arc lies on the meridian of phi + pi
    const double lo = std::cos(std::min(std::numbers::pi, d + w)), hi = std::cos(std::max(0.0, d - w));
    return std::max(0.0, std::min(hi, z_hi) - std::max(lo, z_lo));
}

/// The mass of the cap's density 1 over the cell [u0, u1] x [v0, v1] of
/// (phi, z), another way: over phi, the meridians' overlaps (cap_overlap),
/// cut where they are not smooth (where an end of the meridian's arc crosses
/// z = v0 or v1, found by bisection on 1024 steps, and at the meridians that
/// touch the cap, where the arc's ends move as a square root), each piece by
/// tanh-sinh quadrature, which integrates such end points to 1e-14.
double cap_cell_reference(double a, double rho, const ParamRect& r) {
    const auto ends = [&](double phi) {
        const double k = std::cos(phi) * std::sin(a), c = std::cos(a), big_r = std::hypot(k, c);
        if (std::cos(rho) > big_r) return std::array<double, 2>{2.0, 2.0};
        const double d = std::atan2(k, c), w = std::acos(std::cos(rho) / big_r);
        return std::array<double, 2>{std::cos(std::min(std::numbers::pi, d + w)), std::cos(std::max(0.0, d - w))};
    };
    std::vector<double> cuts = {r.u0, r.u1};
    const double touch = std::acos(std::sqrt(std::cos(rho) * std::cos(rho) - std::cos(a) * std::cos(a)) / std::sin(a));
    for (const double t : {touch, -touch, 2.0 * std::numbers::pi - touch})
        if (t > r.u0 && t < r.u1) cuts.push_back(t);
    constexpr int kSteps = 1024;
    for (const double z : {r.v0, r.v1})
        for (int e = 0; e < 2; ++e) {
            const auto side = [&](double phi) { return ends(phi)[static_cast<std::size_t>(e)] > z; };
            for (int i = 0; i < kSteps; ++i) {
                double p = r.u0 + (r.u1 - r.u0) * i / kSteps, q = r.u0 + (r.u1 - r.u0) * (i + 1) / kSteps;
                if (side(p) == side(q)) continue;
                const bool at_p = side(p);
                for (int k = 0; k < 100; ++k) {
                    const double m = 0.5 * (p + q);
                    (side(m) == at_p ? p : q) = m;
                }
                cuts.push_back(0.5 * (p + q));
            }
        }
    std::sort(cuts.begin(), cuts.end());
    boost::math::quadrature::tanh_sinh<double> integrator;
    const auto overlap = [&](double phi) { return cap_overlap(phi, a, rho, r.v0, r.v1); };
    double sum = 0.0;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
        if (!(cuts[i + 1] > cuts[i])) continue;
        // A piece of under 1e-9 of the side (two kinks a bisection apart):
        // tanh-sinh's abscissas do not resolve it; there the 15-point rule,
        // whose error on a piece that narrow is below 1e-18 of the cell.
        if (cuts[i + 1] - cuts[i] < 1e-9 * (r.u1 - r.u0))
            sum += boost::math::quadrature::gauss_kronrod<double, 15>::integrate(overlap, cuts[i], cuts[i + 1], 0);
        else
            sum += integrator.integrate(overlap, cuts[i], cuts[i + 1], 1e-14);
    }
    return sum;
}

// The same for a cap tilted 50 degrees, whose rim crosses cells along
// curves: every cell within its own bound (or the bound's 2^-20 of the value
// of rounding slack, verify_cell's) of its mass computed another way
// (cap_cell_reference), and within the accuracy rule (1% of its Poisson
// deviation at 10^6 samples) where its bound says the rule was not met.
TEST(QuadratureEdges, ATiltedCapsRimAcrossCellsKeepsEveryBoundAgainstAnotherReference) {
    const Binning b(Domain::sphere());
    const double a = 50.0 * std::numbers::pi / 180.0, rho = 0.3, mass = 2.0 * std::numbers::pi * (1.0 - std::cos(rho));
    const double ax = std::sin(a), az = std::cos(a);
    QuadratureOptions opt;
    opt.verify = true;
    const CellIntegrals q = integrate_cells(b, pointwise([&](const DomainPoint& p) {
        return p[0] * ax + p[2] * az >= std::cos(rho) ? 1.0 / mass : 0.0;
    }), opt);
    EXPECT_NEAR(q.total, 1.0, q.error_total + 1e-12);
    std::size_t rim = 0;
    for (std::size_t c = 0; c < b.cell_count(); ++c) {
        const ParamRect r = b.cell_rect(c);
        const double exact = cap_cell_reference(a, rho, r) / mass, d = std::abs(q.probability[c] - exact);
        if (exact > 0.0 && exact < 0.999 * b.cell_measure(c) / mass) ++rim;
        EXPECT_LE(d, q.error[c] + 0x1p-20 * exact) << c << " " << q.probability[c] << " vs " << exact;
        if (q.error[c] <= cell_tolerance(q.probability[c], opt)) {
            EXPECT_LE(d, cell_tolerance(exact, opt)) << c;
        }
    }
    EXPECT_GT(rim, 20u) << "the rim should cross many cells";
}

TEST(Quadrature, HalfLineIncludesTheTail) {
    const Binning b(Domain::half_line(2.0), {20, 0, 1.0});
    const double rate = 0.7;
    const CellIntegrals q =
        integrate_cells(b, pointwise([&](const DomainPoint& p) { return rate * std::exp(-rate * (p[0] - 2.0)); }), {});
    EXPECT_NEAR(q.total, 1.0, 1e-9);
    // The tail cell: exp(-rate * (start - a)).
    const std::size_t tail = b.cell_count() - 1;
    const double start = b.point_at(b.cell_rect(tail).u0, 0.5)[0];
    EXPECT_NEAR(q.probability[tail], std::exp(-rate * (start - 2.0)), 1e-9);
}

TEST(Quadrature, DiskUsesAreaMeasure) {
    const Binning b(Domain::unit_disk());
    // Density 2 (1 - r^2) / pi on the unit disk integrates to 1.
    const CellIntegrals q = integrate_cells(
        b, pointwise([](const DomainPoint& p) { return 2 * (1 - p[0] * p[0] - p[1] * p[1]) / std::numbers::pi; }), {});
    EXPECT_NEAR(q.total, 1.0, 1e-12);
}

TEST(Quadrature, BadDensitiesAreCounted) {
    const Binning b(Domain::interval(0, 1), {10, 0, 1.0});
    const CellIntegrals nan = integrate_cells(b, pointwise([](const DomainPoint& p) { return p[0] > 0.5 ? std::nan("") : 1.0; }), {});
    EXPECT_GT(nan.nonfinite_values, 0u);
    EXPECT_TRUE(std::isnan(nan.total));
    const CellIntegrals neg = integrate_cells(b, pointwise([](const DomainPoint& p) { return p[0] - 0.25; }), {});
    EXPECT_GT(neg.negative_values, 0u);
}

TEST(Quadrature, ResultDoesNotDependOnTheExecutor) {
    const Binning b(Domain::hemisphere());
    const BatchPdf pdf = pointwise([](const DomainPoint& p) { return ggx_pdf(p[2], 0.2) * (1 + 0.3 * p[0]); });
    const CellIntegrals serial = integrate_cells(b, pdf, {});
    // Two threads taking indices from a shared counter, in no fixed order.
    const ParallelFor threaded = [](std::size_t n, const std::function<void(std::size_t)>& body) {
        std::atomic<std::size_t> next{0};
        auto work = [&] {
            for (std::size_t i; (i = next.fetch_add(1)) < n;) body(i);
        };
        std::thread other(work);
        work();
        other.join();
    };
    const CellIntegrals parallel = integrate_cells(b, pdf, {}, threaded);
    EXPECT_EQ(serial.probability, parallel.probability);
    EXPECT_EQ(serial.total, parallel.total);
    EXPECT_EQ(serial.evaluations, parallel.evaluations);
}

}  // namespace
}  // namespace warpcheck::chi2
