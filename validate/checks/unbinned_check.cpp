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
// Samples come from map_input_chunks (chunk c from ctx.chunk_rng(c)); the
// transforms F(t) are gathered in chunk order and sorted, so every figure is
// the same for any thread count.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "chi2/marginal_cdf.h"
#include "chi2/min_p.h"
#include "chi2/power.h"
#include "chi2/unbinned.h"
#include "validate/checks/checks.h"
#include "validate/checks/evidence.h"
#include "validate/checks/input_chunks.h"
#include "validate/checks/line_resolution.h"
#include "validate/checks/power_level.h"

namespace warpcheck {
namespace {

/// Strips per marginal CDF. The linear interpolation's error ~h^2 |F''| / 8 is
/// ~1e-7 |F''| at 1024 strips, far below the tests' 1/sqrt(N) = 1e-3 where the
/// marginal density is smooth on the strips' scale (and measured: cdf_error).
constexpr int kStrips = 1024;
/// The cubature's accuracy fraction (chi2/quadrature.h) for the strips: the
/// summed error allowance f sqrt(strips / N) is then 3% of 1/sqrt(N) at worst.
constexpr double kCdfAccuracyFraction = 1e-3;
/// A CDF error e moves sqrt(N) D by sqrt(N) e. Allowing 0.1 of that scale
/// moves a p-value near the tests' critical values (~2 to 3) by a few percent
/// of itself at most. A marginal whose tabulated CDF is less accurate (a
/// density peaked within a few strips) is not tested, and the result says so.
constexpr double kCdfErrorScale = 0.1;

/// One marginal: a name, how to read its coordinate off a sample, its CDF, and
/// the test that judges it.
struct Marginal {
    std::string label;
    std::function<double(const WarpOutput&)> coordinate;
    chi2::MarginalCdf cdf;
    chi2::UnbinnedTest judged_by = chi2::UnbinnedTest::AndersonDarling;
};

/// Whether parameter `axis` of the domain is an azimuth (a circle: where it
/// starts is arbitrary). The one place this check looks at the domain's kind.
bool is_azimuth(const chi2::Domain& domain, int axis) {
    return axis == 0 && domain.azimuthal();
}

/// The test that judges a marginal. Kuiper on an azimuth: the only one of the
/// three that does not depend on where the circle is cut. Anderson-Darling on
/// every other coordinate: it weights the tails, and it detects the tilt family
/// with the smallest deviation of the three (see the power figures). KS is
/// computed and reported but not judged: every judged test costs all the
/// others power through the correction (with 6 tests instead of 2, the
/// cos^(1 + 0.01) claim of tests/validate/test_unbinned_check.cpp is caught in
/// 7 of 10 seeds instead of 9).
chi2::UnbinnedTest judging_test(const chi2::Domain& domain, int axis) {
    return is_azimuth(domain, axis) ? chi2::UnbinnedTest::Kuiper : chi2::UnbinnedTest::AndersonDarling;
}

chi2::BatchPdf batch_pdf(const WarpCase& warp) {
    return [&warp](std::span<const chi2::DomainPoint> points, std::span<double> density) {
        std::vector<WarpOutput> x(points.size());
        for (std::size_t i = 0; i < points.size(); ++i)
            x[i] = {static_cast<float>(points[i][0]), static_cast<float>(points[i][1]),
                    static_cast<float>(points[i][2])};
        warp.pdf(x, density);
    };
}

chi2::ParallelFor parallel(const CheckContext& ctx) {
    return [&ctx](std::size_t n, const std::function<void(std::size_t)>& body) { ctx.parallel_for(n, body); };
}

/// Refinement of the strips where the density is peaked (chi2/marginal_cdf.h):
/// pairs of strips whose interpolation error estimate exceeds 0.03 / sqrt(N)
/// are halved, up to 8 times the uniform grid's strips in all. With the
/// quadrature's allowance (3% of 1/sqrt(N) at 1024 strips, 8.5% at the full
/// budget, as a worst case: the strips' actual error estimates are what is
/// judged) the CDF then stays within the judge's kCdfErrorScale.
chi2::CdfRefinement refinement(uint64_t samples) {
    chi2::CdfRefinement r;
    r.interpolation_target = 0.03 / std::sqrt(static_cast<double>(samples));
    r.max_strips = 8 * kStrips;
    return r;
}

/// Rows per strip when strips across a 2D domain miss mass: the cubature's
/// first nodes across a whole strip can fall on either side of a peak that is
/// narrow in the other parameter (a sharp lobe's cos theta under the phi
/// strips); 16 rows at the other marginal's quantiles give the peak rows of
/// its own.
constexpr int kRowsWhenMassMissed = 16;

std::vector<Marginal> natural_marginals(const WarpCase& warp, const CheckContext& ctx,
                                        const chi2::QuadratureOptions& q) {
    const chi2::BinResolution line = line_resolution(warp);
    const int dims = warp.domain().point_dimension() == 1 ? 1 : 2;
    std::vector<Marginal> out(static_cast<std::size_t>(dims));
    // The last parameter first: its CDF places the rows of the first's strips.
    for (int axis = dims - 1; axis >= 0; --axis) {
        const chi2::Binning strips = chi2::strip_binning(warp.domain(), axis, kStrips, line);
        Marginal& m = out[static_cast<std::size_t>(axis)];
        m.label = axis == 0 ? strips.u_label() : strips.v_label();
        m.coordinate = [strips, axis](const WarpOutput& o) { return strips.parameters_of(to_domain_point(o))[axis]; };
        chi2::CdfRefinement r = refinement(q.sample_count);
        m.cdf = chi2::tabulate_marginal_cdf(strips, axis, batch_pdf(warp), q, parallel(ctx), r);
        const chi2::MarginalCdf* other = dims == 2 && axis == 0 ? &out[1].cdf : nullptr;
        if (other && !(std::abs(m.cdf.total - other->total) <= m.cdf.error_bound() + other->error_bound())) {
            r.cross_cuts = chi2::quantile_cuts(*other, kRowsWhenMassMissed);
            const uint64_t spent = m.cdf.evaluations;
            m.cdf = chi2::tabulate_marginal_cdf(strips, axis, batch_pdf(warp), q, parallel(ctx), r);
            m.cdf.evaluations += spent;
        }
        m.judged_by = judging_test(warp.domain(), axis);
    }
    return out;
}

/// The declared 1D views on a 2D domain that are bounded (no tail mass) and
/// coordinates the natural marginals do not already test, each a marginal.
std::vector<Marginal> declared_marginals(const WarpCase& warp, const std::vector<Marginal>& natural,
                                         const chi2::QuadratureOptions& q) {
    std::vector<Marginal> out;
    if (natural.size() < 2) return out;
    for (const MonotoneMarginal& view : warp.info().views) {
        if (view.tail_mass != 0.0 || view.lower_tail_mass != 0.0 || !view.pdf || !view.coordinate) continue;
        if (std::any_of(natural.begin(), natural.end(), [&](const Marginal& m) { return m.label == view.label; }))
            continue;
        const chi2::Binning strips(chi2::Domain::interval(view.lo, view.hi), {kStrips, 0, 0.0});
        const chi2::BatchPdf pdf = [&view](std::span<const chi2::DomainPoint> points, std::span<double> density) {
            for (std::size_t i = 0; i < points.size(); ++i) density[i] = view.pdf(points[i][0]);
        };
        out.push_back(Marginal{view.label, view.coordinate,
                               chi2::tabulate_marginal_cdf(strips, 0, pdf, q, chi2::serial_for,
                                                           refinement(q.sample_count)),
                               chi2::UnbinnedTest::AndersonDarling});
    }
    return out;
}

/// Per chunk: each marginal's probability transforms F(t), and the samples
/// whose coordinate was NaN (counted per marginal, not transformed).
struct ChunkTransforms {
    std::vector<std::vector<double>> u;
    std::vector<uint64_t> nan;
};

/// The compute part: marginal CDFs, then the samples' transforms, sorted.
struct Computed {
    std::vector<Marginal> marginals;
    std::vector<std::vector<double>> sorted_u;
    std::vector<uint64_t> nan;
    std::vector<chi2::UnbinnedStatistics> stats;
};

Computed compute(const WarpCase& warp, const CheckContext& ctx) {
    chi2::QuadratureOptions q;
    q.sample_count = ctx.options().samples;
    q.accuracy_fraction = kCdfAccuracyFraction;
    Computed c;
    c.marginals = natural_marginals(warp, ctx, q);
    for (Marginal& m : declared_marginals(warp, c.marginals, q)) c.marginals.push_back(std::move(m));
    const std::size_t k = c.marginals.size();
    const auto parts = map_input_chunks<ChunkTransforms>(
        ctx, warp.input_kind(), ctx.options().samples, false, [&](std::size_t, std::span<const WarpInput> in) {
            std::vector<WarpOutput> out(in.size());
            warp.sample(in, out);
            ChunkTransforms t{std::vector<std::vector<double>>(k), std::vector<uint64_t>(k, 0)};
            for (std::size_t m = 0; m < k; ++m) {
                t.u[m].reserve(out.size());
                for (const WarpOutput& o : out) {
                    const double x = c.marginals[m].coordinate(o);
                    if (std::isnan(x)) ++t.nan[m];
                    else t.u[m].push_back(c.marginals[m].cdf(x));
                }
            }
            return t;
        });
    c.sorted_u.assign(k, {});
    c.nan.assign(k, 0);
    for (const ChunkTransforms& p : parts)
        for (std::size_t m = 0; m < k && !p.u.empty(); ++m) {
            c.sorted_u[m].insert(c.sorted_u[m].end(), p.u[m].begin(), p.u[m].end());
            c.nan[m] += p.nan[m];
        }
    ctx.parallel_for(k, [&](std::size_t m) { chi2::sort_unit_values(c.sorted_u[m]); });
    for (std::size_t m = 0; m < k; ++m) c.stats.push_back(chi2::unbinned_statistics(c.sorted_u[m]));
    return c;
}

/// "cos theta" -> "cos_theta": the marginal's label as part of a figure name.
std::string figure_label(const std::string& label) {
    std::string s;
    for (char ch : label) s += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return s;
}

/// The CDF's error: the tabulation's own bound, plus how far the strips'
/// total misses 1. A correct density integrates to 1 to float precision (the
/// chi2 check judges that); a larger shortfall means the cubature missed part
/// of a peak that lies between its nodes across the whole strip, and then the
/// CDF is wrong by at least that much.
double cdf_error(const Marginal& m) { return m.cdf.error_bound() + std::abs(m.cdf.total - 1.0); }

bool accurate(const Marginal& m, uint64_t samples) {
    return cdf_error(m) <= kCdfErrorScale / std::sqrt(static_cast<double>(samples));
}

/// The judge part. One p-value per check: the smallest of the judged tests'
/// p-values (one per accurately tabulated marginal, see judging_test),
/// Sidak-corrected over their number (exact for independent marginals,
/// conservative for correlated ones), so the runner's family counts stay honest. A density that does not integrate
/// to a positive finite number is an Error: there is no CDF to test against.
/// Returns the number of tests.
int judge(CheckResult& r, const Computed& c, uint64_t samples) {
    std::vector<std::string> errors, skipped;
    std::vector<double> p_values;
    for (std::size_t m = 0; m < c.marginals.size(); ++m) {
        const chi2::MarginalCdf& cdf = c.marginals[m].cdf;
        if (!(cdf.total > 0.0 && std::isfinite(cdf.total)))
            errors.push_back(fmt::format("the density integrates to {} over the domain", cdf.total));
        if (!accurate(c.marginals[m], samples)) {
            skipped.push_back(fmt::format("{} (CDF error {:.2g})", c.marginals[m].label, cdf_error(c.marginals[m])));
            continue;
        }
        p_values.push_back(c.stats[m].p_value(c.marginals[m].judged_by));
    }
    const int tests = static_cast<int>(p_values.size());
    const double p_min = tests == 0 ? std::nan("") : *std::min_element(p_values.begin(), p_values.end());
    if (tests > 0) r.p_value = chi2::sidak_min_p(p_values);
    r.figures.push_back({"p_value", r.p_value.value_or(std::nan(""))});
    r.figures.push_back({"tests", static_cast<double>(tests)});
    r.figures.push_back({"untested_marginals", static_cast<double>(skipped.size())});
    r.summary = tests == 0 ? "not applicable: no marginal CDF accurate enough"
                           : fmt::format("min p {:.3g} over {} tests, corrected {:.3g}", p_min, tests, *r.p_value);
    if (!skipped.empty()) r.summary += "; untested: " + join_reasons(skipped);
    r.verdict = errors.empty() ? Verdict::Pass : Verdict::Error;
    r.message = join_reasons(errors);
    return tests;
}

/// Figures per marginal and test, and the stated power: the smallest tilt of
/// a marginal (chi2/power.h) each test detects with 90% probability at the
/// planned per-test level, corrected like the p-value; "power_tilt_eps" is
/// the largest over the judged marginals' tests (each marginal is judged by
/// one test, and this tilt is detected on whichever marginal it lies).
void add_figures(CheckResult& r, const Computed& c, const RunOptions& options, int tests) {
    r.samples = options.samples;
    const double level = power_level(options, tests);
    double worst = 0.0;
    for (chi2::UnbinnedTest t : chi2::kUnbinnedTests) {
        const double eps = chi2::unbinned_tilt_for_power(t, level, options.samples);
        r.figures.push_back({fmt::format("power_{}_tilt_eps", chi2::short_name(t)), eps});
        for (std::size_t m = 0; m < c.marginals.size(); ++m)
            if (c.marginals[m].judged_by == t && accurate(c.marginals[m], options.samples)) worst = std::max(worst, eps);
    }
    r.figures.push_back({"power_tilt_eps", worst > 0.0 ? worst : std::nan("")});
    r.figures.push_back({"power_level", level});
    for (std::size_t m = 0; m < c.marginals.size(); ++m) {
        const std::string name = figure_label(c.marginals[m].label);
        for (chi2::UnbinnedTest t : chi2::kUnbinnedTests) {
            r.figures.push_back({fmt::format("{}_{}_statistic", name, chi2::short_name(t)), c.stats[m].statistic(t)});
            r.figures.push_back({fmt::format("{}_{}_p_value", name, chi2::short_name(t)), c.stats[m].p_value(t)});
        }
        r.figures.push_back({name + "_cdf_error", cdf_error(c.marginals[m])});
        r.figures.push_back({name + "_cdf_integral", c.marginals[m].cdf.total});
        r.figures.push_back({name + "_cdf_evaluations", static_cast<double>(c.marginals[m].cdf.evaluations)});
        r.figures.push_back({name + "_nan", static_cast<double>(c.nan[m])});
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
    Table t{"Unbinned tests per marginal (judged: one per marginal, where its CDF error is below 0.1 / sqrt(n))",
            {"marginal", "test", "judged", "statistic", "p-value", "CDF error"}, {}};
    for (std::size_t m = 0; m < c.marginals.size(); ++m)
        for (chi2::UnbinnedTest test : chi2::kUnbinnedTests)
            t.rows.push_back({c.marginals[m].label, std::string(chi2::short_name(test)),
                              test == c.marginals[m].judged_by ? "yes" : "no", fmt::format("{:.5g}", c.stats[m].statistic(test)),
                              fmt::format("{:.3g}", c.stats[m].p_value(test)),
                              fmt::format("{:.2g}", cdf_error(c.marginals[m]))});
    r.tables.push_back(std::move(t));
}

class UnbinnedCheck final : public Check {
public:
    std::string name() const override { return "unbinned"; }
    bool statistical() const override { return true; }
    std::string description() const override {
        return "KS, Kuiper and Anderson-Darling tests of each marginal against its CDF from the pdf (Sidak over the "
               "tests)";
    }
    bool applies_to(const WarpCase& warp) const override { return warp.has_pdf() && !warp.is_discrete(); }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const Computed c = compute(warp, ctx);
        CheckResult r;
        const int tests = std::max(1, judge(r, c, ctx.options().samples));
        add_figures(r, c, ctx.options(), tests);
        if (r.p_value) r.summary += fmt::format("; 90% power: tilt {:.2g}", *r.figure("power_tilt_eps"));
        add_evidence(r, c, warp.name(), power_level(ctx.options(), tests));
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_unbinned_check() { return std::make_unique<UnbinnedCheck>(); }

}  // namespace warpcheck
