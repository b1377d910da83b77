// "unbinned": Kolmogorov-Smirnov, Kuiper and Anderson-Darling tests of the
// samples' marginals against the marginal CDFs of the case's own density
// (chi2/unbinned.h), where Pearson's binned statistic is weakest: broad, smooth
// deviations of shape.
//
// Marginals: the domain's parameters (chi2::Binning): x for 1D domains, x and y
// on boxes, phi and r^2 on the disk, phi and cos theta on spherical caps; plus
// the case's declared 1D views (WarpCaseInfo::views) on 2D domains when they are
// a different coordinate. Each marginal's CDF is tabulated from the pdf by the
// engine's cubature (chi2/marginal_cdf.h) and normalised by the density's
// integral: whether that integral is 1 is the chi2 check's rule, this one
// judges shape.
//
// The null hypothesis is what a float warp can produce: the ideal continuous
// distribution, each output coordinate moved by the warp's own rounding (a few
// float steps, chi2/float_band.h), and the CDF known to its error bound (which
// is checked against a finer tabulation before it is relied on). Where both
// together shift the CDF by less than kCdfErrorScale / sqrt(N), the ordinary
// statistics are used. Elsewhere (a tiny cap has a few hundred distinct values
// of cos theta; a density with a jump has a less accurate CDF) each sample's
// transform is known only within a band, and the test is against that band
// (chi2::banded_statistics: conservative p-values), with its power stated for
// the band (chi2/banded_power.h). A sample without a coordinate (NaN, or the
// azimuth of the pole) is left out and counted, and the fraction left out is
// carried into the band; a warp whose samples all lack one fails.
//
// Samples come from map_input_chunks (chunk c from ctx.chunk_rng(c)); the
// transforms F(t) are gathered in chunk order and sorted, so every figure is
// the same for any thread count.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "chi2/banded_power.h"
#include "chi2/float_band.h"
#include "chi2/marginal_cdf.h"
#include "chi2/min_p.h"
#include "chi2/power.h"
#include "chi2/unbinned.h"
#include "validate/api/light_case.h"
#include "validate/checks/shared/cell_power.h"
#include "reports/result_tables.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/direction_length.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/input_chunks.h"
#include "validate/checks/shared/line_resolution.h"
#include "validate/checks/shared/power_level.h"

namespace warpcheck {
namespace {

/// Strips per marginal CDF. The linear interpolation's error ~h^2 |F''| / 8 is
/// ~1e-7 |F''| at 1024 strips, far below the tests' 1/sqrt(N) = 1e-3 where the
/// marginal density is smooth on the strips' scale (and measured: cdf_error).
constexpr int kStrips = 1024;
/// The cubature's accuracy fraction (chi2/quadrature.h) for the strips: the
/// summed error allowance f sqrt(strips / N) is then 3% of 1/sqrt(N) at worst.
constexpr double kCdfAccuracyFraction = 1e-3;
/// A shift e of the CDF (its tabulation error, or samples moved by float
/// rounding) moves sqrt(N) D by at most sqrt(N) e. At 0.1 that is 4% of a
/// critical value near 2.5 and, in the worst case of every sample moved the
/// same way, a p-value near the level by a factor e^(4 * 2.5 * 0.1) = 2.7 at
/// most (rounding to nearest moves samples both ways, and an error bound is
/// rarely met). Below it the ordinary statistics are used (the largest such
/// shift among the built-in cases is 0.067: trowbridge_reitz_visible's
/// cos theta); above it the shift is carried into the test as a band.
constexpr double kCdfErrorScale = 0.1;
/// How far the ideal point may lie from a float output, in float steps of each
/// coordinate (chi2/float_band.h): correct rounding is within one step, and a
/// few rounded operations whose terms are no larger than the result (pbrt's
/// cone, (1 - u) + u cos_max: 1.25 ulp at most, measured) within two.
constexpr int kFloatSteps = 2;
/// --strict: the output must be the ideal value correctly rounded.
constexpr int kStrictFloatSteps = 1;
/// A CDF error of 10% of the mass or more leaves a band test that sees only
/// what the chi2 check's cells see with certainty, and it would cost the other
/// tests power through the correction: such a marginal is left untested, and
/// the row says so with its error.
constexpr double kMaxCdfBand = 0.1;

/// Rows test up to this many p-values (an azimuth two, every other marginal
/// one) at the levels whose simulated power prepare() computes beforehand.
constexpr int kPreparedTestCounts = 4;

/// How a marginal's CDF is tabulated: strips, the cubature's accuracy
/// fraction, and the refinement's target as a multiple of 1/sqrt(N).
struct TableSpec {
    int strips = kStrips;
    double accuracy_fraction = kCdfAccuracyFraction;
    double target_scale = 0.03;
    /// The density's points (directions) scaled by this before they are
    /// rounded to float: the pdf's response to its input's length (see
    /// measure_length_shift). 1 for the table that is tested against.
    double input_scale = 1.0;
};
/// A CDF whose error is carried into the test is tabulated again like this to
/// check its error (check_cdf_error): about twice the strips (2 x 1021, 1021
/// prime: no edge but the ends and the middle is an edge of the first table,
/// so an error tied to where the cubature's nodes fall, such as a jump along
/// the cells' diagonals, does not repeat), a quarter of the cubature's
/// allowance, half the refinement target.
constexpr TableSpec kCheckTable{2 * 1021, kCdfAccuracyFraction / 4.0, 0.015};

using Tabulate = std::function<chi2::MarginalCdf(const TableSpec&)>;
using BandOf = std::function<chi2::ParameterBand(const WarpOutput&)>;

/// One marginal: a name, how to read its coordinate (and the band of the
/// ideal point's) off a sample, its CDF and that CDF's error, and the tests
/// that judge it.
struct Marginal {
    std::string label;
    /// A domain parameter's band (chi2/float_band.h), called directly in the
    /// samples' loop; else `band` (a declared view's).
    std::optional<chi2::FloatResolution> resolution_of_parameter;
    BandOf band;
    /// When set, no sample's band is computed: every band is at most this
    /// probability (see band_model).
    std::optional<double> band_model;
    std::string resolution;  ///< how the band is set, for the row's text
    Tabulate tabulate;
    chi2::MarginalCdf cdf;
    double cdf_error = 0.0;  ///< the bound the judge uses (see cdf_error_of)
    /// The largest difference to a finer tabulation, where one was made.
    std::optional<double> table_difference;
    /// How far the CDF moves when the pdf's input directions are longer or
    /// shorter by the source's length_mismatch (measure_length_shift), carried
    /// into the test with the CDF's error; the pilot's estimate where that is
    /// negligible and not carried (length_shift_measured false).
    double length_shift = 0.0;
    bool length_shift_measured = false;
    double length_delta = 0.0;  ///< the relative length change it was measured for
    std::vector<chi2::UnbinnedTest> judged_by;
};

/// Whether parameter `axis` of the domain is an azimuth (a circle: where it
/// starts is arbitrary). The one place this check looks at the domain's kind.
bool is_azimuth(const chi2::Domain& domain, int axis) {
    return axis == 0 && domain.azimuthal();
}

/// The tests that judge a marginal. Anderson-Darling on every coordinate: it
/// weights the tails, and it detects the tilt family with the smallest
/// deviation of the three (see the power figures). On an azimuth, Kuiper as
/// well: the only one of the three that does not depend on where the circle is
/// cut (a deviation that straddles phi = 0 is one deviation to it). Kuiper
/// alone there missed a missing sliver of 0.1% of the azimuth next to the cut,
/// which A^2 saw at p 2e-5: the sliver is in A^2's weighted tail.
/// (tests/validate/checks/unbinned/test_unbinned_resolution.cpp: at 2 10^6 samples the check
/// rejects it on 5 of 5 seeds, Kuiper alone on 1.) KS is computed and
/// reported but not judged: every judged test costs all the others power
/// through the correction (with 6 tests instead of 2, the cos^(1 + 0.01) claim
/// of tests/validate/checks/unbinned/test_unbinned_check.cpp is caught in 7 of 10 seeds
/// instead of 9; with 3, A^2 judging the azimuth too, still in 9).
std::vector<chi2::UnbinnedTest> judging_tests(const chi2::Domain& domain, int axis) {
    if (is_azimuth(domain, axis)) return {chi2::UnbinnedTest::Kuiper, chi2::UnbinnedTest::AndersonDarling};
    return {chi2::UnbinnedTest::AndersonDarling};
}

/// The warp's pdf at the points, each scaled by `scale` (a direction made
/// longer or shorter: see measure_length_shift) and rounded to float.
chi2::BatchPdf batch_pdf(const WarpCase& warp, double scale = 1.0) {
    return [&warp, scale](std::span<const chi2::DomainPoint> points, std::span<double> density) {
        std::vector<WarpOutput> x(points.size());
        for (std::size_t i = 0; i < points.size(); ++i)
            x[i] = {static_cast<float>(scale * points[i][0]), static_cast<float>(scale * points[i][1]),
                    static_cast<float>(scale * points[i][2])};
        warp.pdf(x, density);
    };
}

chi2::ParallelFor parallel(const CheckContext& ctx) {
    return [&ctx](std::size_t n, const std::function<void(std::size_t)>& body) { ctx.parallel_for(n, body); };
}

/// The refinement budget of one piece of a CDF strip (chi2::QuadratureOptions):
/// 128 regions (127 halvings, each of the region whose error is largest). A
/// piece that has not met the accuracy rule by then holds a jump or a density
/// that float rounding makes jagged (the edge of a 1e-4 annulus), which further
/// halvings shrink only in proportion: there 1024 regions cost 7x the
/// evaluations (3.9e9 in the row's tabulations, 50 s) for 0.2% less stated error. Its error estimate is carried into the
/// CDF's error either way; no row of validate --all needs more than 128.
constexpr std::size_t kCdfPieceRegions = 128;

chi2::QuadratureOptions quadrature(uint64_t samples, const TableSpec& spec) {
    chi2::QuadratureOptions q;
    q.sample_count = samples;
    q.accuracy_fraction = spec.accuracy_fraction;
    q.max_regions_per_cell = kCdfPieceRegions;
    return q;
}

/// Refinement of the strips where the density is peaked (chi2/marginal_cdf.h):
/// pairs of strips whose interpolation error estimate exceeds 0.03 / sqrt(N)
/// are halved, up to 8 times the uniform grid's strips in all. With the
/// quadrature's allowance (3% of 1/sqrt(N) at 1024 strips, 8.5% at the full
/// budget, as a worst case: the strips' actual error estimates are what is
/// judged) the CDF then stays within the judge's kCdfErrorScale.
chi2::CdfRefinement refinement(uint64_t samples, const TableSpec& spec) {
    chi2::CdfRefinement r;
    r.interpolation_target = spec.target_scale / std::sqrt(static_cast<double>(samples));
    r.max_strips = 8 * static_cast<std::size_t>(spec.strips);
    return r;
}

/// Rows per strip when strips across a 2D domain miss mass: the cubature's
/// first nodes across a whole strip can fall on either side of a peak that is
/// narrow in the other parameter (a sharp lobe's cos theta under the phi
/// strips); 16 rows at the other marginal's quantiles give the peak rows of
/// its own.
constexpr int kRowsWhenMassMissed = 16;

/// A pilot sample's size for placing strips (pilot_strip_binning): 16 points
/// per quantile strip of the table.
constexpr std::size_t kPilotSize = 16 * kStrips;

/// The pilot's outputs (UnbinnedSource::draw on the pilot inputs).
std::vector<WarpOutput> draw_pilot(const WarpCase& warp, const CheckContext& ctx, const UnbinnedSource& source) {
    std::vector<WarpOutput> out;
    source.draw(pilot_inputs(ctx, warp.input_kind(), kPilotSize), out);
    return out;
}

Tabulate natural_tabulator(const WarpCase& warp, const CheckContext& ctx, int axis, std::vector<double> cuts,
                           std::shared_ptr<const std::vector<double>> pilot) {
    return [&warp, &ctx, axis, cuts = std::move(cuts), pilot](const TableSpec& spec) {
        // Strips where the pilot's mass lies as well as uniform ones
        // (pilot_strip_binning): a small light between the uniform strips'
        // nodes would integrate to nothing.
        const chi2::Binning strips =
            chi2::pilot_strip_binning(warp.domain(), axis, spec.strips, *pilot, line_resolution(warp));
        chi2::CdfRefinement r = refinement(ctx.options().samples, spec);
        r.cross_cuts = cuts;
        return chi2::tabulate_marginal_cdf(strips, axis, batch_pdf(warp, spec.input_scale),
                                           quadrature(ctx.options().samples, spec), parallel(ctx), r);
    };
}

int float_steps(const RunOptions& options) { return options.strict ? kStrictFloatSteps : kFloatSteps; }

/// Rows across a strip where the pilot's values of the other parameter are
/// concentrated (all within a quarter of its range: a small light, a thin
/// ring, a lobe at the pole): cuts at the values' ends, widened by a quarter
/// of their spread, and at their 16-quantiles, so that the cubature's nodes
/// across the strip fall on the support instead of stepping over it. Empty
/// where the values spread wider (the cubature sees them).
std::vector<double> pilot_cross_cuts(std::vector<double> values, double lo, double hi) {
    std::erase_if(values, [](double v) { return !std::isfinite(v); });
    if (values.size() < 16) return {};
    std::sort(values.begin(), values.end());
    const double spread = values.back() - values.front();
    if (!(spread < 0.25 * (hi - lo))) return {};
    const double margin = std::max(0.25 * spread, 0x1p-40 * (hi - lo));
    std::vector<double> cuts{values.front() - margin};
    for (int k = 1; k < kRowsWhenMassMissed; ++k)
        cuts.push_back(values[values.size() * static_cast<std::size_t>(k) / kRowsWhenMassMissed]);
    cuts.push_back(values.back() + margin);
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    return cuts;
}

std::vector<Marginal> natural_marginals(const WarpCase& warp, const CheckContext& ctx,
                                        const std::vector<WarpOutput>& pilot) {
    const int dims = warp.domain().point_dimension() == 1 ? 1 : 2;
    std::vector<Marginal> out(static_cast<std::size_t>(dims));
    std::vector<std::shared_ptr<std::vector<double>>> values(static_cast<std::size_t>(dims));
    for (int axis = 0; axis < dims; ++axis) {
        const chi2::Binning strips = chi2::strip_binning(warp.domain(), axis, kStrips, line_resolution(warp));
        Marginal& m = out[static_cast<std::size_t>(axis)];
        m.label = axis == 0 ? strips.u_label() : strips.v_label();
        m.resolution_of_parameter.emplace(strips, axis, float_steps(ctx.options()));
        m.resolution = m.resolution_of_parameter->describe();
        auto& v = values[static_cast<std::size_t>(axis)];
        v = std::make_shared<std::vector<double>>();
        for (const WarpOutput& o : pilot)
            if (warp.domain().contains(to_domain_point(o))) v->push_back(m.resolution_of_parameter->value(o));
    }
    // The last parameter first: its CDF places the rows of the first's strips.
    for (int axis = dims - 1; axis >= 0; --axis) {
        Marginal& m = out[static_cast<std::size_t>(axis)];
        std::vector<double> cross;
        if (dims == 2) {
            const chi2::ParamRect b = chi2::Binning(warp.domain(), line_resolution(warp)).parameter_bounds();
            cross = axis == 0 ? pilot_cross_cuts(*values[1], b.v0, b.v1) : pilot_cross_cuts(*values[0], b.u0, b.u1);
        }
        m.tabulate = natural_tabulator(warp, ctx, axis, cross, values[static_cast<std::size_t>(axis)]);
        m.cdf = m.tabulate(TableSpec{});
        const chi2::MarginalCdf* other = dims == 2 && axis == 0 ? &out[1].cdf : nullptr;
        if (other && !(std::abs(m.cdf.total - other->total) <= m.cdf.error_bound() + other->error_bound())) {
            m.tabulate = natural_tabulator(warp, ctx, axis, chi2::quantile_cuts(*other, kRowsWhenMassMissed),
                                           values[static_cast<std::size_t>(axis)]);
            const uint64_t spent = m.cdf.evaluations;
            m.cdf = m.tabulate(TableSpec{});
            m.cdf.evaluations += spent;
        }
        m.judged_by = judging_tests(warp.domain(), axis);
    }
    return out;
}

/// A declared view's band: its coordinate is any function of the output, so
/// each float coordinate is moved `steps` floats up and the changes summed,
/// either way (to first order, the view's range over the box of moved
/// outputs; the step up is the larger one where the two differ, at a power
/// of two such as z = 1). A move that makes the view undefined (NaN) bounds
/// nothing and is left out.
BandOf probed_band(std::function<double(const WarpOutput&)> coordinate, int dims, int steps) {
    return [coordinate = std::move(coordinate), dims, steps](const WarpOutput& o) {
        chi2::ParameterBand b;
        b.value = coordinate(o);
        double h = 0.0;
        for (int k = 0; k < dims; ++k) {
            WarpOutput moved = o;
            float& c = moved[static_cast<std::size_t>(k)];
            for (int s = 0; s < steps; ++s) c = std::nextafter(c, std::numeric_limits<float>::infinity());
            const double change = std::abs(coordinate(moved) - b.value);
            if (!std::isnan(change)) h += change;
        }
        b.lo = b.value - h;
        b.hi = b.value + h;
        return b;
    };
}

/// The declared 1D views on a 2D domain that are bounded (no tail mass) and
/// coordinates the natural marginals do not already test, each a marginal.
std::vector<Marginal> declared_marginals(const WarpCase& warp, const CheckContext& ctx,
                                         const std::vector<Marginal>& natural) {
    std::vector<Marginal> out;
    if (natural.size() < 2) return out;
    const uint64_t samples = ctx.options().samples;
    for (const MonotoneMarginal& view : warp.info().views) {
        if (view.tail_mass != 0.0 || view.lower_tail_mass != 0.0 || !view.pdf || !view.coordinate) continue;
        if (std::any_of(natural.begin(), natural.end(), [&](const Marginal& m) { return m.label == view.label; }))
            continue;
        Marginal m;
        m.label = view.label;
        m.band = probed_band(view.coordinate, warp.domain().point_dimension(), float_steps(ctx.options()));
        m.resolution = fmt::format("{} float steps of each coordinate, to first order", float_steps(ctx.options()));
        m.tabulate = [&view, samples](const TableSpec& spec) {
            const chi2::Binning strips(chi2::Domain::interval(view.lo, view.hi), {spec.strips, 0, 0.0});
            const chi2::BatchPdf pdf = [&view](std::span<const chi2::DomainPoint> points, std::span<double> density) {
                for (std::size_t i = 0; i < points.size(); ++i) density[i] = view.pdf(points[i][0]);
            };
            return chi2::tabulate_marginal_cdf(strips, 0, pdf, quadrature(samples, spec), chi2::serial_for,
                                               refinement(samples, spec));
        };
        m.cdf = m.tabulate(TableSpec{});
        m.judged_by = {chi2::UnbinnedTest::AndersonDarling};
        out.push_back(std::move(m));
    }
    return out;
}

/// The CDF's error: the tabulation's own bound, plus how far the strips'
/// total misses the density's integral (1 for a warp's density, which
/// integrates to 1 to float precision: the chi2 check judges that; else the
/// source's, within its bound). A larger shortfall means the cubature missed
/// part of a peak that lies between its nodes across the whole strip, and
/// then the CDF is wrong by at least that much.
double cdf_error_of(const chi2::MarginalCdf& cdf, const UnbinnedSource& source) {
    return cdf.error_bound() + std::abs(cdf.total - source.total) + source.total_error;
}

/// The largest |F1 - F2| of two tabulated CDFs: both are linear between their
/// edges, so the largest difference is at an edge of one of them.
double largest_difference(const chi2::MarginalCdf& a, const chi2::MarginalCdf& b) {
    double d = 0.0;
    for (double t : a.edges) d = std::max(d, std::abs(a(t) - b(t)));
    for (double t : b.edges) d = std::max(d, std::abs(a(t) - b(t)));
    return std::isnan(a.total) || std::isnan(b.total) ? std::nan("") : d;
}

/// Sets m.cdf_error. A CDF error above the scale the ordinary tests ignore is
/// carried into the test as a band, so it must not understate the true error
/// (a jump through the cubature's nodes can make it do so): the marginal is
/// tabulated again (kCheckTable) and the finer table is used, with the larger
/// of its own error and the largest difference d between the two tables. If
/// the finer table at least halves the true error (about twice the strips halve
/// an interpolation error at a jump and quarter it elsewhere; the cubature's
/// allowance is a quarter), |err2| <= |err1| / 2 and |err1| <= d + |err2| give
/// |err2| <= d: a stated error that is itself wrong is replaced by a measured
/// one. Costs one finer tabulation, only for such marginals.
void check_cdf_error(Marginal& m, uint64_t samples, const UnbinnedSource& source) {
    m.cdf_error = cdf_error_of(m.cdf, source);
    if (m.cdf_error <= kCdfErrorScale / std::sqrt(static_cast<double>(samples))) return;
    if (!(std::isfinite(m.cdf.total) && m.cdf.total > 0.0)) return;  // no CDF to check: judged an error
    chi2::MarginalCdf finer = m.tabulate(kCheckTable);
    const double d = largest_difference(m.cdf, finer);
    finer.evaluations += m.cdf.evaluations;
    m.table_difference = d;
    m.cdf = std::move(finer);
    m.cdf_error = std::max(cdf_error_of(m.cdf, source), d);
    if (std::isnan(d)) m.cdf_error = d;
}

/// How a marginal is tested.
enum class Mode {
    Exact,      ///< the ordinary statistics: float resolution and CDF error are negligible
    Banded,     ///< against the band of float resolution and CDF error
    Untested,   ///< the CDF error is too large (kMaxCdfBand) or undefined
    NoSamples,  ///< no sample at all
    AllNaN,     ///< every sample's coordinate is NaN
    NoDensity,  ///< the density does not integrate to a positive finite number
};

/// Per chunk and marginal: the transforms F(t) of the samples' coordinates,
/// the half-width of each one's float band in probability (the larger side,
/// rounded up to a float: a symmetric band that holds the true one; 1 for an
/// azimuth band across the cut, which may hold either end), the samples whose
/// coordinate was NaN (counted, not transformed), and the widest band.
struct ChunkTransforms {
    std::vector<double> u;
    std::vector<float> band;
    uint64_t nan = 0;
    double float_band = 0.0;
};

/// The compute part's results per marginal.
struct Computed {
    std::vector<Marginal> marginals;
    std::vector<std::vector<double>> sorted_u;
    std::vector<uint64_t> nan;
    /// Samples whose point itself has a NaN coordinate (the warp returned NaN),
    /// of all drawn: a failure, whatever their share, as in chi2.
    uint64_t nan_points = 0, drawn = 0;
    /// The largest probability between a sample's transform and an end of its
    /// float band: how far float rounding may have moved the CDF.
    std::vector<double> float_band;
    std::vector<Mode> mode;
    std::vector<std::size_t> distinct;  ///< distinct transforms (distinct coordinates)
    std::vector<chi2::UnbinnedStatistics> stats;
    std::vector<PhaseTime> phases;  ///< wall time of the compute part's steps (validate --timings)
};

/// A marginal whose bands the model puts below this fraction of the
/// negligible shift needs no sample's band: the model reads the density off
/// the strips, which may average a peak a few times higher within one, and a
/// tenth leaves that room. Saves three quarters of the transforms' cost on
/// the marginals that float resolution cannot move (most of them).
constexpr double kModelBandFraction = 0.1;

/// The pilot's estimate of the pdf's response to the length of its input
/// directions (UnbinnedSource::length_mismatch): 2 E|e| over the pilot's directions,
/// e = pdf(x (1 +- delta)) / pdf(x) - 1, the larger of the two, capped at 1
/// (a NaN counts 1). A density multiplied by 1 + e has a CDF within
/// 2 E_p|e| of the first (|int_{<t} p e - F(t) int p e| <= 2 int p |e|, to
/// first order), and the pilot's directions are drawn from p.
double pilot_length_response(const WarpCase& warp, const std::vector<WarpOutput>& pilot, double delta) {
    std::vector<WarpOutput> x, longer, shorter;
    for (const WarpOutput& o : pilot) {
        if (!warp.domain().contains(to_domain_point(o))) continue;
        x.push_back(o);
        longer.push_back(scaled_direction(o, 1.0 + delta));
        shorter.push_back(scaled_direction(o, 1.0 - delta));
    }
    std::vector<double> p(x.size()), pl(x.size()), ps(x.size());
    warp.pdf(x, p);
    warp.pdf(longer, pl);
    warp.pdf(shorter, ps);
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (!(p[i] > 0.0)) continue;  // a sample where pdf = 0 is judged by the other checks
        const double e = std::max(std::abs(pl[i] - p[i]), std::abs(ps[i] - p[i])) / p[i];
        sum += e <= 1.0 ? e : 1.0;
        ++n;
    }
    return n == 0 ? 0.0 : 2.0 * sum / static_cast<double>(n);
}

/// The table that measures the pdf's response to its directions' length: a
/// quarter of the tested table's accuracy (its error bound, 4 times larger,
/// is carried with the response, which is scaled by delta / kLengthProbe,
/// an eighth at theta_o 91): it adds about a tenth to the row's tabulation
/// on a sharp lobe (glass at alpha 1e-4, theta_o 91: 9.5e8 CDF evaluations
/// instead of 8.6e8).
constexpr TableSpec kLengthTable{kStrips, 4.0 * kCdfAccuracyFraction, 4.0 * 0.03, 1.0 + kLengthProbe};

/// Sets each natural marginal's length_shift (directions only, 3D points),
/// for a source whose pdf compares its input with a direction of known length
/// error delta (a BSDF's wo): the pilot's estimate; where that is above a
/// tenth of the negligible shift (the same fraction as band_model's), the
/// measured one, carried into the test with the CDF's error. Measured: the
/// CDF tabulated with every direction handed to the pdf kLengthProbe longer
/// (to first order, the response to shorter is its negative), the largest
/// difference d to the tested table plus both tables' error bounds (the
/// response lies within that of d), scaled by delta / kLengthProbe while d
/// is under kMaxCdfBand (a response small against the lobe: first order),
/// unscaled beyond (no first-order claim). delta alone: the tabulation's own
/// rounding of its nodes to float is zero-mean and averages over a strip's
/// nodes, as the samples' does.
void measure_length_shift(std::vector<Marginal>& marginals, const WarpCase& warp, const CheckContext& ctx,
                          const std::vector<WarpOutput>& pilot, double delta) {
    if (warp.domain().point_dimension() != 3 || !(delta > 0.0)) return;
    const double scale = std::min(1.0, delta / kLengthProbe);
    const double estimate = scale * pilot_length_response(warp, pilot, std::max(delta, kLengthProbe));
    const double small = kModelBandFraction * kCdfErrorScale / std::sqrt(static_cast<double>(ctx.options().samples));
    for (Marginal& m : marginals) {
        m.length_shift = estimate;
        m.length_delta = delta;
        if (!(estimate > small)) continue;
        TableSpec spec = kLengthTable;
        spec.input_scale = 1.0 + std::max(delta, kLengthProbe);
        const chi2::MarginalCdf moved = m.tabulate(spec);
        const double d = largest_difference(m.cdf, moved);
        m.length_shift = d < kMaxCdfBand ? scale * (d + m.cdf.error_bound() + moved.error_bound()) : d;
        m.length_shift_measured = true;
        m.cdf.evaluations += moved.evaluations;
    }
}

/// Sets m.band_model where the model of a parameter's float band
/// (chi2::largest_band_probability) is far below the negligible shift.
void band_model(Marginal& m, uint64_t samples) {
    if (!m.resolution_of_parameter) return;
    const double model = chi2::largest_band_probability(*m.resolution_of_parameter, m.cdf);
    if (model <= kModelBandFraction * kCdfErrorScale / std::sqrt(static_cast<double>(samples))) m.band_model = model;
}

ChunkTransforms transform(const Marginal& m, std::span<const WarpOutput> out) {
    ChunkTransforms t;
    t.u.reserve(out.size());
    if (m.band_model) {
        t.float_band = *m.band_model;
        for (const WarpOutput& o : out) {
            const double v = m.resolution_of_parameter->value(o);
            if (std::isnan(v)) ++t.nan;
            else t.u.push_back(m.cdf(v));
        }
        return t;
    }
    t.band.reserve(out.size());
    for (const WarpOutput& o : out) {
        const chi2::ParameterBand b = m.resolution_of_parameter ? m.resolution_of_parameter->band(o) : m.band(o);
        if (std::isnan(b.value)) {
            ++t.nan;
            continue;
        }
        const chi2::MarginalCdf::AtBand f = m.cdf.at_band(b.lo, b.value, b.hi);
        const double half = std::max(f.hi - f.value, f.value - f.lo);
        t.float_band = std::max(t.float_band, half);
        t.u.push_back(f.value);
        // Rounded to nearest, half (1 + 2^-22) is at least half.
        t.band.push_back(b.wraps ? 1.0f : static_cast<float>(half * (1.0 + 0x1p-22)));
    }
    return t;
}

/// Samples every chunk and gathers each marginal's transforms and bands in chunk order.
/// The points of `out` with a NaN among the domain's `dimension` coordinates.
uint64_t nan_points(std::span<const WarpOutput> out, int dimension) {
    uint64_t n = 0;
    for (const WarpOutput& o : out) {
        bool nan = false;
        for (int i = 0; i < dimension; ++i) nan = nan || std::isnan(o[static_cast<std::size_t>(i)]);
        n += nan;
    }
    return n;
}

void gather(Computed& c, const WarpCase& warp, const CheckContext& ctx, const UnbinnedSource& source,
            std::vector<std::vector<float>>& band) {
    const std::size_t k = c.marginals.size();
    struct Part {
        std::vector<ChunkTransforms> t;
        uint64_t nan_points = 0, drawn = 0;
    };
    const int dimension = warp.domain().point_dimension();
    auto chunks = map_input_chunks<Part>(
        ctx, warp.input_kind(), ctx.options().samples, false, [&](std::size_t, std::span<const WarpInput> in) {
            std::vector<WarpOutput> out;
            source.draw(in, out);
            Part part{{}, nan_points(out, dimension), out.size()};
            for (std::size_t m = 0; m < k; ++m) part.t.push_back(transform(c.marginals[m], out));
            return part;
        });
    std::vector<std::vector<ChunkTransforms>> parts;
    for (Part& p : chunks) {
        c.nan_points += p.nan_points;
        c.drawn += p.drawn;
        parts.push_back(std::move(p.t));
    }
    c.sorted_u.assign(k, {});
    band.assign(k, {});
    c.nan.assign(k, 0);
    c.float_band.assign(k, 0.0);
    for (std::size_t m = 0; m < k; ++m) {  // each marginal's whole size at once: no copies as it grows
        std::size_t values = 0, bands = 0;
        for (const auto& p : parts) {
            values += p[m].u.size();
            bands += p[m].band.size();
        }
        c.sorted_u[m].reserve(values);
        band[m].reserve(bands);
    }
    for (const auto& p : parts)
        for (std::size_t m = 0; m < p.size(); ++m) {
            c.sorted_u[m].insert(c.sorted_u[m].end(), p[m].u.begin(), p[m].u.end());
            band[m].insert(band[m].end(), p[m].band.begin(), p[m].band.end());
            c.nan[m] += p[m].nan;
            c.float_band[m] = std::max(c.float_band[m], p[m].float_band);
        }
}

/// How far the law of the samples tested may lie from the tabulated CDF: its
/// error, plus the fraction of samples left out for a NaN coordinate (the
/// azimuth of the pole, where rounding gathers a neighbourhood of it): the
/// law of the rest differs from the whole's by at most the left-out
/// probability p / (1 - p), estimated by the count.
double cdf_shift(const Computed& c, std::size_t m) {
    const double kept = static_cast<double>(c.sorted_u[m].size()), left_out = static_cast<double>(c.nan[m]);
    const double p = left_out / (kept + left_out);
    return c.marginals[m].cdf_error + (left_out > 0.0 ? p / (1.0 - p) : 0.0);
}

Mode mode_of(const Computed& c, std::size_t m, uint64_t samples) {
    const Marginal& marginal = c.marginals[m];
    if (c.sorted_u[m].empty()) return c.nan[m] > 0 ? Mode::AllNaN : Mode::NoSamples;
    if (!(marginal.cdf.total > 0.0 && std::isfinite(marginal.cdf.total))) return Mode::NoDensity;
    if (!(cdf_shift(c, m) < kMaxCdfBand)) return Mode::Untested;
    const double shift = c.float_band[m] + cdf_shift(c, m);
    return std::sqrt(static_cast<double>(samples)) * shift <= kCdfErrorScale ? Mode::Exact : Mode::Banded;
}

std::size_t distinct_values(const std::vector<double>& sorted) {
    std::size_t k = sorted.empty() ? 0 : 1;
    for (std::size_t i = 1; i < sorted.size(); ++i) k += sorted[i] != sorted[i - 1];
    return k;
}

/// The banded statistics of marginal m: each sample's interval is its float
/// band moved out by the CDF's shift (cdf_shift: the law of the samples
/// tested lies within it of the tabulated CDF); the ends sorted apart.
chi2::UnbinnedStatistics banded(const Computed& c, std::size_t m, const std::vector<double>& u,
                                const std::vector<float>& band) {
    const double e = cdf_shift(c, m);
    std::vector<double> lo(u.size()), hi(u.size());
    for (std::size_t i = 0; i < u.size(); ++i) {
        const double b = band.empty() ? c.float_band[m] : static_cast<double>(band[i]);
        lo[i] = std::clamp(u[i] - b - e, 0.0, 1.0);
        hi[i] = std::clamp(u[i] + b + e, 0.0, 1.0);
    }
    chi2::sort_unit_values(lo);
    chi2::sort_unit_values(hi);
    return chi2::banded_statistics(lo, hi);
}

/// The compute part: marginal CDFs, then the samples' transforms, sorted, and
/// each marginal's statistics, ordinary or banded.
Computed compute(const WarpCase& warp, const CheckContext& ctx, const UnbinnedSource& source) {
    using Clock = std::chrono::steady_clock;
    const auto seconds = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
    const uint64_t samples = ctx.options().samples;
    const auto start = Clock::now();
    Computed c;
    const std::vector<WarpOutput> pilot = draw_pilot(warp, ctx, source);
    c.marginals = natural_marginals(warp, ctx, pilot);
    measure_length_shift(c.marginals, warp, ctx, pilot, source.length_mismatch);
    for (Marginal& m : declared_marginals(warp, ctx, c.marginals)) c.marginals.push_back(std::move(m));
    for (Marginal& m : c.marginals) {
        check_cdf_error(m, samples, source);
        if (m.length_shift_measured) m.cdf_error += m.length_shift;
        band_model(m, samples);
    }
    const auto tabulated = Clock::now();
    const std::size_t k = c.marginals.size();
    std::vector<std::vector<float>> band;
    gather(c, warp, ctx, source, band);
    const auto sampled = Clock::now();
    c.stats.assign(k, {});
    for (std::size_t m = 0; m < k; ++m) c.mode.push_back(mode_of(c, m, samples));
    ctx.parallel_for(k, [&](std::size_t m) {
        if (c.mode[m] == Mode::Banded) c.stats[m] = banded(c, m, c.sorted_u[m], band[m]);
        chi2::sort_unit_values(c.sorted_u[m]);
        if (c.mode[m] != Mode::Banded) c.stats[m] = chi2::unbinned_statistics(c.sorted_u[m]);
    });
    for (std::size_t m = 0; m < k; ++m) c.distinct.push_back(distinct_values(c.sorted_u[m]));
    c.phases = {{"CDF tabulation", seconds(start, tabulated)},
                {"sampling+transforms", seconds(tabulated, sampled)},
                {"sorting+statistics", seconds(sampled, Clock::now())}};
    return c;
}

/// A number for a row's text: NaN is written out as "undefined", never "nan".
std::string number(double v, int digits = 2) {
    return std::isnan(v) ? "undefined" : fmt::format("{:.{}g}", v, digits);
}

/// What a banded marginal's row says: the band's half-width, and each part
/// of it that is not a small fraction of the negligible shift: the float
/// quantisation, the CDF error carried into the test, the samples left out.
std::string band_note(const Computed& c, std::size_t m, uint64_t samples) {
    const Marginal& marginal = c.marginals[m];
    const double small = kModelBandFraction * kCdfErrorScale / std::sqrt(static_cast<double>(samples));
    std::vector<std::string> parts;
    if (c.float_band[m] >= small)
        parts.push_back(fmt::format("quantised: tested on {} distinct values, band +-{} ({} of the mass)",
                                    c.distinct[m], marginal.resolution, number(c.float_band[m])));
    if (marginal.cdf_error >= small) {
        std::string s = fmt::format("CDF error +-{} carried into the test", number(marginal.cdf_error));
        if (marginal.table_difference)
            s += fmt::format(" (a finer tabulation differs by {})", number(*marginal.table_difference));
        if (marginal.length_shift_measured && marginal.length_shift >= small)
            s += fmt::format(" (of it +-{}: the pdf's response to its directions {} longer or shorter, the length "
                             "error of the direction it compares them with)",
                             number(marginal.length_shift), number(marginal.length_delta));
        parts.push_back(s);
    }
    if (c.nan[m] > 0)
        parts.push_back(fmt::format("{} samples without a {} left out (+-{} carried into the test)", c.nan[m],
                                    marginal.label, number(cdf_shift(c, m) - marginal.cdf_error)));
    std::string note =
        fmt::format("{} against a band of +-{}: ", marginal.label, number(c.float_band[m] + cdf_shift(c, m)));
    for (std::size_t i = 0; i < parts.size(); ++i) note += (i ? ", " : "") + parts[i];
    return note;
}

/// The verdict when something other than the p-value decides: a sample whose
/// point is NaN, or every sample's coordinate NaN, is a failure of the warp
/// (before any error: an error must never hide a failure), a density without
/// a finite integral an error (there is no CDF to test against; said once
/// however many marginals lack it), nothing tested is not applicable.
bool judge_without_p_value(CheckResult& r, const Computed& c, const std::vector<std::string>& untested, int tests) {
    if (c.nan_points > 0) {
        r.verdict = Verdict::Fail;
        r.p_value.reset();  // decided without a level
        const bool all = c.nan_points == c.drawn;
        r.summary = all ? "every sample has a NaN coordinate"
                        : fmt::format("{} of {} samples have NaN coordinates", c.nan_points, c.drawn);
        r.message = r.summary + (all ? ": nothing to test" : "") +
                    ": a sampler must return a point (NaN fails whatever its share, as in chi2)";
        return true;
    }
    std::vector<std::string> all_nan, errors;
    bool any_samples = false;
    for (std::size_t m = 0; m < c.marginals.size(); ++m) {
        any_samples = any_samples || c.mode[m] != Mode::NoSamples;
        if (c.mode[m] == Mode::AllNaN) all_nan.push_back(c.marginals[m].label);
        const std::string error = fmt::format("the density integrates to {} over the domain", c.marginals[m].cdf.total);
        if (c.mode[m] == Mode::NoDensity && std::find(errors.begin(), errors.end(), error) == errors.end())
            errors.push_back(error);
    }
    if (!all_nan.empty()) {
        r.verdict = Verdict::Fail;
        r.summary = "every sample has a NaN coordinate";
        r.message = all_nan.size() == c.marginals.size()
                        ? "every sample has a NaN coordinate: nothing to test"
                        : "every sample has a NaN coordinate in " + join_reasons(all_nan);
        return true;
    }
    if (!errors.empty()) {
        r.verdict = Verdict::Error;
        r.message = join_reasons(errors);
        if (tests == 0) r.summary = "error: " + errors.front();
        return tests == 0;
    }
    if (tests > 0) return false;
    r.verdict = Verdict::NotApplicable;
    r.summary = !any_samples    ? "not applicable: no samples"
                : untested.empty() ? "not applicable: no marginal to test"
                                   : "not applicable: no marginal CDF accurate enough; untested: " +
                                         join_reasons(untested);
    return true;
}

/// The judge part. One p-value per check: the smallest of the judged tests'
/// p-values (judging_tests, on every marginal tested exactly or against its
/// band), Sidak-corrected over their number (exact for independent tests,
/// conservative for correlated ones), so the runner's family counts stay
/// honest. Returns the number of tests.
int judge(CheckResult& r, const Computed& c, uint64_t samples) {
    std::vector<std::string> untested, notes;
    std::vector<double> p_values;
    for (std::size_t m = 0; m < c.marginals.size(); ++m) {
        if (c.mode[m] == Mode::Untested)
            untested.push_back(fmt::format("{} (CDF error {})", c.marginals[m].label, number(c.marginals[m].cdf_error)));
        if (c.mode[m] != Mode::Exact && c.mode[m] != Mode::Banded) continue;
        for (chi2::UnbinnedTest t : c.marginals[m].judged_by) p_values.push_back(c.stats[m].p_value(t));
        if (c.mode[m] == Mode::Banded) notes.push_back(band_note(c, m, samples));
    }
    const int tests = static_cast<int>(p_values.size());
    if (tests > 0) r.p_value = chi2::sidak_min_p(p_values);
    r.figures.push_back({"p_value", r.p_value.value_or(std::nan(""))});
    r.figures.push_back({"tests", static_cast<double>(tests)});
    r.figures.push_back({"untested_marginals", static_cast<double>(untested.size())});
    r.figures.push_back({"banded_marginals", static_cast<double>(notes.size())});
    r.verdict = Verdict::Pass;
    if (judge_without_p_value(r, c, untested, tests)) return tests;
    const double p_min = *std::min_element(p_values.begin(), p_values.end());
    r.summary = fmt::format("min p {} over {} tests, corrected {}", number(p_min, 3), tests, number(*r.p_value, 3));
    for (const std::string& note : notes) r.summary += "; " + note;
    if (!untested.empty()) r.summary += "; untested: " + join_reasons(untested);
    return tests;
}

/// The smallest tilt that one of marginal m's judged tests detects with 90%
/// probability at `level` (either detecting it suffices). A banded test sees
/// a tilt only beyond its band (chi2/banded_power.h): its interval ends lie
/// within twice the band of the ideal transforms (float band and CDF error
/// each count at the sample and at the band's end). NaN when no stated power
/// is possible.
double marginal_power(const Computed& c, std::size_t m, double level, uint64_t samples) {
    double best = std::nan("");
    const bool banded = c.mode[m] == Mode::Banded;
    const double shift = 2.0 * (c.float_band[m] + cdf_shift(c, m));
    for (chi2::UnbinnedTest t : c.marginals[m].judged_by) {
        const double eps = banded ? chi2::banded_tilt_for_power(t, level, shift, samples)
                                  : chi2::unbinned_tilt_for_power(t, level, samples);
        if (std::isnan(best) || eps < best) best = eps;
    }
    return best;
}

/// Figures per marginal and test, and the stated power: the smallest tilt of
/// a marginal (chi2/power.h) that its judged tests detect with 90%
/// probability at the planned per-test level, corrected like the p-value;
/// "power_tilt_eps" is the largest over the tested marginals (this tilt is
/// detected on whichever marginal it lies).
void add_figures(CheckResult& r, const Computed& c, const RunOptions& options, int tests) {
    r.samples = options.samples;
    // The outputs the source drew (a warp's: every sample; a BSDF's: its
    // continuous samples), each marginal's tested or left out.
    const uint64_t drawn = c.sorted_u.empty() ? options.samples : c.sorted_u[0].size() + c.nan[0];
    r.figures.push_back({"nan_samples", static_cast<double>(c.nan_points)});
    const double level = power_level(options, tests);
    double worst = 0.0;
    for (chi2::UnbinnedTest t : chi2::kUnbinnedTests)
        r.figures.push_back({fmt::format("power_{}_tilt_eps", chi2::short_name(t)),
                             chi2::unbinned_tilt_for_power(t, level, drawn)});
    for (std::size_t m = 0; m < c.marginals.size(); ++m)
        if (c.mode[m] == Mode::Exact || c.mode[m] == Mode::Banded) {
            const double eps = marginal_power(c, m, level, drawn);
            r.figures.push_back({"power_tilt_eps_" + figure_label(c.marginals[m].label), eps});
            worst = std::isnan(eps) || std::isnan(worst) ? std::nan("") : std::max(worst, eps);
        }
    r.figures.push_back({"power_tilt_eps", worst > 0.0 ? worst : std::nan("")});
    r.figures.push_back({"power_level", level});
    for (std::size_t m = 0; m < c.marginals.size(); ++m) {
        const std::string name = figure_label(c.marginals[m].label);
        for (chi2::UnbinnedTest t : chi2::kUnbinnedTests) {
            r.figures.push_back({fmt::format("{}_{}_statistic", name, chi2::short_name(t)), c.stats[m].statistic(t)});
            r.figures.push_back({fmt::format("{}_{}_p_value", name, chi2::short_name(t)), c.stats[m].p_value(t)});
        }
        r.figures.push_back({name + "_cdf_error", c.marginals[m].cdf_error});
        r.figures.push_back({name + "_pdf_length_shift", c.marginals[m].length_shift});
        r.figures.push_back({name + "_pdf_length_shift_carried", c.marginals[m].length_shift_measured ? 1.0 : 0.0});
        r.figures.push_back({name + "_cdf_integral", c.marginals[m].cdf.total});
        r.figures.push_back({name + "_cdf_evaluations", static_cast<double>(c.marginals[m].cdf.evaluations)});
        r.figures.push_back({name + "_nan", static_cast<double>(c.nan[m])});
        r.figures.push_back({name + "_float_band", c.float_band[m]});
        r.figures.push_back({name + "_distinct_values", static_cast<double>(c.distinct[m])});
        r.figures.push_back({name + "_banded", c.mode[m] == Mode::Banded ? 1.0 : 0.0});
    }
}

/// The evidence part: sqrt(n) (F_n - F) against F for each marginal, at 512
/// order statistics, with the KS critical band at the power level; a table of
/// every statistic.
void add_evidence(CheckResult& r, const Computed& c, const std::string& case_name, double level) {
    Plot plot;
    plot.kind = Plot::Kind::Lines;
    plot.title = "unbinned: empirical minus model CDF of " + case_name;
    plot.x_label = "model CDF F";
    plot.y_label = "sqrt(n) (F_n - F)";
    for (std::size_t m = 0; m < c.marginals.size(); ++m) {
        const std::vector<double>& u = c.sorted_u[m];
        Series s{c.marginals[m].label, {}, {}};
        const double n = static_cast<double>(u.size());
        for (std::size_t k = 0; k < 512 && !u.empty(); ++k) {
            const std::size_t i = std::min(u.size() - 1, static_cast<std::size_t>((k + 0.5) / 512.0 * n));
            s.x.push_back(u[i]);
            s.y.push_back(std::sqrt(n) * ((static_cast<double>(i) + 0.5) / n - u[i]));
        }
        plot.series.push_back(std::move(s));
    }
    const double band = chi2::asymptotic_critical_value(chi2::UnbinnedTest::KolmogorovSmirnov, level);
    plot.series.push_back({"KS critical", {0.0, 1.0}, {band, band}});
    plot.series.push_back({"-KS critical", {0.0, 1.0}, {-band, -band}});
    r.plots.push_back(std::move(plot));
    Table t{"Unbinned tests per marginal (judged: A^2, and Kuiper on an azimuth; banded where float resolution and "
            "CDF error together exceed 0.1 / sqrt(n))",
            {"marginal", "test", "judged", "statistic", "p-value", "CDF error", "banded"}, {}};
    for (std::size_t m = 0; m < c.marginals.size(); ++m)
        for (chi2::UnbinnedTest test : chi2::kUnbinnedTests) {
            const auto& judged = c.marginals[m].judged_by;
            t.rows.push_back({c.marginals[m].label, std::string(chi2::short_name(test)),
                              std::find(judged.begin(), judged.end(), test) != judged.end() ? "yes" : "no",
                              fmt::format("{:.5g}", c.stats[m].statistic(test)),
                              fmt::format("{:.3g}", c.stats[m].p_value(test)), number(c.marginals[m].cdf_error),
                              c.mode[m] == Mode::Banded ? "yes" : "no"});
        }
    r.tables.push_back(std::move(t));
}

std::string long_test_name(std::string_view short_name) {
    if (short_name == "ad") return "Anderson\u2013Darling A\u00b2";
    if (short_name == "kuiper") return "Kuiper V";
    if (short_name == "ks") return "Kolmogorov\u2013Smirnov D";
    return std::string(short_name);
}

/// Each judged test's p-value at the Sidak level over the judged tests.
void unbinned_p_lines(const CheckResult& r, double level, std::vector<JudgedQuantity>& out) {
    const auto judged = judged_unbinned_tests(r);
    const double k = r.figure("tests").value_or(static_cast<double>(judged.size()));
    if (judged.empty() || !(k >= 1.0)) return;
    const double per_test = -std::expm1(std::log1p(-level) / k);  // Sidak: 1 - (1 - level)^(1/k)
    for (const auto& [marginal, test] : judged) {
        std::string name;
        for (char ch : marginal) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
        name += "_" + test;
        const auto p = r.figure(name + "_p_value");
        if (!p) continue;
        out.push_back(p_line(fmt::format("{}: {} = {:.4g}, p-value", marginal, long_test_name(test),
                                         r.figure(name + "_statistic").value_or(NAN)),
                             *p, per_test, fmt::format(" (level, \u0160id\u00e1k over {})", judged_number(k))));
    }
}

class UnbinnedCheck final : public Check {
public:
    std::string name() const override { return "unbinned"; }
    JudgedRules judged_rules() const override { return unbinned_judged_rules(); }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "The empirical CDF of each marginal against the CDF of the pdf: Anderson\u2013Darling on "
                "every marginal, and Kuiper too on an azimuth (KS is shown, not judged); where float resolution and "
                "the CDF's error could shift the CDF, each sample is tested within its band (conservative p); a "
                "marginal whose CDF is not accurate enough is left untested.",
                "1 \u2212 (1 \u2212 min p)^k, \u0160id\u00e1k over the k judged tests. The summary's \u201cmin "
                "p\u201d is before the correction."};
    }
    std::string description() const override {
        return "KS, Kuiper and Anderson-Darling tests of each marginal against its CDF from the pdf, allowing for "
               "float resolution and the CDF's error (Sidak over the tests)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        // A light's marginals in the sphere's (phi, cos theta) chart cannot
        // resolve a light a few degrees across (its tables find no mass in a
        // cap 1e-3 rad wide, and see a triangle 0.5 rad wide with too little
        // power to state), while chi2's cells, placed by a pilot of the
        // light, test its distribution where it is.
        if (declines_samples(warp))
            return Applicability::lacks(std::string(as_mis(warp) != nullptr ? "an MIS case's light" : "a light") +
                                        "'s marginals in the sphere's chart do not resolve it; chi2's cells "
                                        "placed around it test its distribution");
        return Applicability::when(warp.has_pdf() && !warp.is_discrete());
    }

    /// The simulated power every row states (add_figures: each test at the
    /// level of 1 to 4 tests in the row, what a case's marginals give) and the
    /// banded simulation's bridges, computed once for the run's workers.
    void prepare(const RunOptions& options) const override {
        for (int tests = 1; tests <= kPreparedTestCounts; ++tests)
            for (chi2::UnbinnedTest t : chi2::kUnbinnedTests)
                (void)chi2::unbinned_tilt_for_power(t, power_level(options, tests), options.samples);
        chi2::prepare_banded_power();
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const auto samples = [&warp](std::span<const WarpInput> in, std::vector<WarpOutput>& out) {
            out.resize(in.size());
            warp.sample(in, out);
        };
        return run_unbinned(warp, ctx, {samples});
    }
};

}  // namespace

CheckResult run_unbinned(const WarpCase& warp, const CheckContext& ctx, const UnbinnedSource& source) {
    const Computed c = compute(warp, ctx, source);
    CheckResult r;
    r.phases = c.phases;
    const int tests = std::max(1, judge(r, c, ctx.options().samples));
    add_figures(r, c, ctx.options(), tests);
    const double eps = r.figure("power_tilt_eps").value_or(std::nan(""));
    if (r.verdict == Verdict::Pass && std::isfinite(eps)) r.summary += fmt::format("; 90% power: tilt {:.2g}", eps);
    // A banded marginal whose band leaves no power, or too little for a 5%
    // tilt, makes the row weak: it says what it could not see.
    if (r.verdict == Verdict::Pass && r.p_value) r.weak = weakness(r);
    add_evidence(r, c, warp.name(), power_level(ctx.options(), tests));
    return r;
}

std::unique_ptr<Check> make_unbinned_check() { return std::make_unique<UnbinnedCheck>(); }

namespace {

const Series* series_labelled(const Plot& plot, const std::string& label) {
    for (const Series& s : plot.series)
        if (s.label == label && s.x.size() == s.y.size() && !s.x.empty()) return &s;
    return nullptr;
}

/// Kuiper's V = D+ + D-: its two excursions, the highest and lowest points of
/// sqrt(n) (F_n - F).
void mark_kuiper(Plot& plot, const Series& s) {
    const auto [lo, hi] = std::minmax_element(s.y.begin(), s.y.end());
    const auto x_of = [&](auto it) { return s.x[static_cast<std::size_t>(it - s.y.begin())]; };
    plot.highlights.push_back({x_of(hi), *hi, s.label + ": D\u207a"});
    plot.highlights.push_back({x_of(lo), *lo, s.label + ": D\u207b"});
}

/// Anderson-Darling's A^2 integrates n (F_n - F)^2 / (F (1 - F)) over F: its
/// largest term, often in a tail where the curve itself looks small.
void mark_anderson_darling(Plot& plot, const Series& s) {
    double best = -1.0;
    std::size_t at = 0;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
        const double f = s.x[i];
        if (!(f > 0.0 && f < 1.0) || !std::isfinite(s.y[i])) continue;
        const double term = s.y[i] * s.y[i] / (f * (1.0 - f));
        if (term > best) best = term, at = i;
    }
    if (best >= 0.0) plot.highlights.push_back({s.x[at], s.y[at], s.label + ": largest A\u00b2 term"});
}

/// On each plot of sqrt(n) (F_n - F): where each judged test takes its value.
void mark_unbinned_plots(CheckResult& r) {
    const auto judged = judged_unbinned_tests(r);
    for (Plot& plot : r.plots) {
        if (plot.kind != Plot::Kind::Lines) continue;
        for (const auto& [marginal, test] : judged) {
            const Series* s = series_labelled(plot, marginal);
            if (!s) continue;
            if (test == "kuiper") mark_kuiper(plot, *s);
            if (test == "ad") mark_anderson_darling(plot, *s);
        }
        plot.note = "Judged per marginal: Anderson\u2013Darling's A\u00b2 (the integral of the squared curve over "
                    "F(1 \u2212 F); its largest term is ringed), and on an azimuth Kuiper's V = D\u207a + D\u207b too "
                    "(the ringed highest and lowest points). The \u00b1KS lines are for scale: KS is not judged.";
    }
}

}  // namespace

JudgedRules unbinned_judged_rules() {
    return {.figures = {{"nan_samples", "samples with NaN coordinates (any fails)", FigureRule::Zero}},
            .p_values = unbinned_p_lines,
            .p_value = "p-value: smallest judged p, \u0160id\u00e1k-corrected over the judged tests",
            .marks = mark_unbinned_plots};
}

}  // namespace warpcheck
