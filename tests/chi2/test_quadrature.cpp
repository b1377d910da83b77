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
