// "bsdf_chi2": where the continuous lobes send wi, against pdf(wo, .), on the
// whole sphere (reflection and transmission together), with the chi-square
// engine of chi2/. And whether pdf(wo, .) integrates to what the continuous
// lobes hold: one minus the delta lobes' claimed probability, less the
// probability that the sampler gives up (no sample).
//
// The draws split three ways: delta samples (their share is bsdf_delta's
// test), no sample, and continuous samples, which land on the sphere. Given
// how many landed, those are independent draws from pdf(wo, .) / T, T the
// integral of the pdf over the sphere: the chi-square test of their cells
// (chi2::evaluate_chi2 with each cell's integral over T) tests the shape.
// The scale is tested by where the draws went:
//  - T may not exceed 1 - P_delta (P_delta: the delta lobes' claimed
//    probability) by more than the quadrature's verified error bound plus
//    2^-20 (the float rounding of the density, as chi2::kIntegralTolerance)
//    plus, unless --strict, twice the pdf's float noise (its change over one
//    float step of wi, chi2::kFloatNoiseFactor: a float pdf of a sharp lobe
//    rounds its half vector and its 1 / (4 wo.wm)): a FAIL;
//  - the share of non-delta draws that landed is Binomial with probability
//    T / (1 - P_delta) (the rest gave up): its two-sided p-value, against that
//    probability widened by the same tolerance, joins Pearson's and the
//    largest residual's in one p-value (weighted Bonferroni, chi2/min_p.h), so
//    a pdf too small for the samples (1/pi typed as 0.318) fails by chance
//    at most at the run's level.
// The cells and the statistic are those of the chi2 check (chi2_check.cpp):
// cells no narrower than the float steps of their edges allow
// (chi2::float_aware_resolution), the quadrature verified and its float noise
// measured, and each cell's expected count known within a band (the verified
// bound, the float noise and chi2::kEdgeFloatSteps float steps at each edge)
// that Pearson's statistic and the largest residual allow for, so a sharp lobe
// (alpha 0.05) and the horizon, where the float wi crowd onto few floats, are
// judged at what a float sampler can do. A cell integrated as zero where
// continuous samples landed is integrated again around them, as the chi2
// check does (integrate_and_draw); a sample where the pdf is still 0 is a
// failure, and a failure is reported before any error. Where the tolerance
// of T is as large as T itself (a lobe so sharp that the float pdf's noise
// exceeds its integral: Henyey-Greenstein at g = 0.9999, whose peak is
// narrower than the float directions around it), no cell's expected count is
// known within 100%, and the row is not applicable with that reason, its
// failures (samples off the sphere, NaN, in cells of pdf 0) still judged.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "chi2/chi2_test.h"
#include "chi2/equal_probability.h"
#include "chi2/local_residual.h"
#include "chi2/min_p.h"
#include "chi2/power.h"
#include "validate/checks/bsdf/bsdf_checks.h"
#include "validate/checks/shared/cell_evidence.h"
#include "validate/checks/bsdf/bsdf_common.h"
#include "validate/checks/bsdf/bsdf_evidence.h"
#include "validate/checks/bsdf/bsdf_statistics.h"
#include "validate/checks/shared/cell_power.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/input_chunks.h"
#include "validate/checks/shared/power_level.h"

namespace warpcheck::bsdf {
namespace {

/// The share of the check's level given to the landing test; Pearson's
/// statistic and the largest residual share the rest as in the chi2 check.
constexpr double kLandingLevelShare = 0.1;

struct Draws {
    chi2::Histogram hist;
    uint64_t total = 0, no_sample = 0;
    DeltaTally delta;
    void merge(const Draws& o) {
        if (hist.counts.empty()) hist.counts.assign(o.hist.counts.size(), 0);
        hist.merge(o.hist);
        total += o.total;
        no_sample += o.no_sample;
        delta.merge(o.delta);
    }
    /// Continuous draws that landed (in a cell, outside, NaN or set aside on the boundary).
    uint64_t landed() const { return total - no_sample - delta.count(); }
};

Draws draw(const BsdfCase& bsdf, const CheckContext& ctx, const chi2::Binning& binning,
           const std::vector<unsigned char>& zero) {
    auto parts = map_bsdf_chunks<Draws>(ctx, bsdf, ctx.options().samples, false,
                                        [&](std::size_t, std::span<const WarpInput>, std::span<const BsdfRecord> rec) {
        Draws d;
        d.hist.counts.assign(binning.cell_count(), 0);
        std::vector<WarpOutput> points;
        points.reserve(rec.size());
        for (const BsdfRecord& r : rec) {
            ++d.total;
            if (!r.sampled()) ++d.no_sample;
            else if (r.delta()) d.delta.add(bsdf, r);
            else points.push_back(r.wi);
        }
        binning.bin(std::span<const std::array<float, 3>>(points), d.hist, zero);
        return d;
    });
    return merge_in_order(parts);
}

/// The expected side and the observed side, as the chi2 check counts them.
struct Counted {
    chi2::CellIntegrals integrals;
    Draws draws;
    std::size_t reintegrated_cells = 0;
    chi2::PilotRefinement pilot_refinement;
};

/// pdf(wo, .) integrated over the cells and the draws binned; then, as the
/// chi2 check does (chi2::run_chi2_test), the cells integrated as zero where
/// continuous samples landed and the pdf is positive at them (a lobe thinner
/// than the cubature's nodes can see) integrated again around those samples,
/// and the same draws binned again if any was. What is still zero there after
/// that is a sample where the pdf is 0: a failure (evaluate_chi2).
Counted integrate_and_draw(const BsdfCase& bsdf, const CheckContext& ctx, const chi2::Binning& binning,
                           std::span<const chi2::SamplePoint> pilot, const chi2::Chi2Options& options) {
    chi2::QuadratureOptions q;
    q.sample_count = ctx.options().samples;
    q.accuracy_fraction = options.accuracy_fraction;
    q.max_regions_per_cell = options.max_regions_per_cell;
    q.verify = true;
    q.float_noise = true;
    Counted c;
    c.integrals = chi2::integrate_cells(binning, pdf_integrand(bsdf), q, ctx.executor());
    c.pilot_refinement = chi2::refine_by_pilot(binning, pilot, pdf_integrand(bsdf), q, c.integrals, ctx.executor());
    c.draws = draw(bsdf, ctx, binning, chi2::zero_cells_of(c.integrals));
    c.reintegrated_cells = chi2::reintegrate_missed_support(binning, c.draws.hist, pdf_integrand(bsdf), q, c.integrals);
    if (c.reintegrated_cells > 0) c.draws = draw(bsdf, ctx, binning, chi2::zero_cells_of(c.integrals));
    return c;
}

/// The cells' integrals over T: the density of a continuous sample given that
/// it landed (errors and float noise scaled alike).
chi2::CellIntegrals conditional(chi2::CellIntegrals q) {
    const double t = q.total;
    if (!(t > 0.0) || !std::isfinite(t)) return q;  // the engine then fails the integral
    q.total = 0.0;
    q.error_total = 0.0;
    q.float_noise_total = 0.0;
    for (std::size_t i = 0; i < q.probability.size(); ++i) {
        q.probability[i] /= t;
        q.error[i] /= t;
        q.total += q.probability[i];
        q.error_total += q.error[i];
        if (i < q.float_noise.size()) {
            q.float_noise[i] /= t;
            q.float_noise_total += q.float_noise[i];
        }
    }
    return q;
}

struct Normalisation {
    double integral = 0.0, tolerance = 0.0, delta = 0.0;
    uint64_t trials = 0, landed = 0;
    double p_value = 1.0;
    std::string failure;
};

Normalisation normalisation(const chi2::CellIntegrals& q, const Draws& d, bool strict) {
    Normalisation n;
    n.integral = q.total;
    n.tolerance = chi2::kIntegralTolerance + q.error_total + (strict ? 0.0 : chi2::kFloatNoiseFactor * q.float_noise_total);
    n.delta = d.delta.claimed();
    n.trials = d.total - d.delta.count();
    n.landed = d.landed();
    const double room = 1.0 - n.delta;
    if (!(n.integral <= room + n.tolerance))
        n.failure = fmt::format("pdf(wo, .) integrates to {:.7g} over the sphere, more than the {:.7g} that the "
                                "continuous lobes hold (1 - {:.7g} claimed by delta samples; tolerance {:.3g})",
                                n.integral, room, n.delta, n.tolerance);
    if (room > 0.0)
        n.p_value = binomial_band_p(n.landed, n.trials, (n.integral - n.tolerance) / room,
                                    (n.integral + n.tolerance) / room);
    return n;
}

void add_figures(CheckResult& r, const chi2::Chi2Outcome& o, const chi2::LocalResidual& local, const Normalisation& n,
                 const Draws& d, const RunOptions& options, const chi2::Binning& binning) {
    r.samples = d.total;
    const double level = (1.0 - chi2::kLocalLevelShare - kLandingLevelShare) * power_level(options, 1);
    r.figures = {{"statistic", o.statistic()},
                 {"dof", static_cast<double>(o.dof())},
                 {"pearson_p_value", o.p_value()},
                 {"local_p_value", local.p_value},
                 {"local_max_residual", local.residual},
                 {"local_cell", static_cast<double>(local.cell)},
                 {"landing_p_value", n.p_value},
                 {"pdf_integral", n.integral},
                 {"integral_tolerance", n.tolerance},
                 {"delta_claimed", n.delta},
                 {"samples", static_cast<double>(d.total)},
                 {"continuous_samples", static_cast<double>(n.landed)},
                 {"delta_samples", static_cast<double>(d.delta.count())},
                 {"no_sample", static_cast<double>(d.no_sample)},
                 {"outside", static_cast<double>(o.histogram.outside)},
                 {"nan", static_cast<double>(o.histogram.nan)},
                 {"zero_expected_hits", static_cast<double>(o.zero_expected_hits)},
                 {"reintegrated_cells", static_cast<double>(o.reintegrated_cells)},
                 {"cells", static_cast<double>(o.expected.size())},
                 {"cells_used", static_cast<double>(o.pearson.terms)},
                 {"noncentrality", o.pearson.noncentrality},
                 {"float_noise", o.integrals.float_noise_total},
                 {"edge_band", o.edge_band_total},
                 {"verification_mismatches", static_cast<double>(o.integrals.verification_mismatches)},
                 {"quadrature_evaluations", static_cast<double>(o.integrals.evaluations)},
                 {"equal_probability_cells", binning.has_own_edges() ? 1.0 : 0.0}};
    // The stated power of the test as it ran, over the samples that landed
    // (validate/checks/shared/cell_power.h).
    add_cell_power(r, binning, o, level, n.landed);
}

void judge(CheckResult& r, const chi2::Chi2Outcome& o, const chi2::LocalResidual& local, const Normalisation& n) {
    const double share = 1.0 - chi2::kLocalLevelShare - kLandingLevelShare;
    if (o.dof() >= 1)
        r.p_value = chi2::weighted_min_p({o.p_value(), local.p_value, n.p_value},
                                         {share, chi2::kLocalLevelShare, kLandingLevelShare});
    else if (o.errors.empty())
        r.p_value = n.p_value;
    r.summary = fmt::format("chi2 {:.1f} dof {} p {:.3g}; landed {} of {} (pdf integral {:.5g})", o.statistic(),
                            o.dof(), o.p_value(), n.landed, n.trials, n.integral);
    if (o.reintegrated_cells > 0) r.summary += fmt::format("; {} cells integrated again around samples", o.reintegrated_cells);
    std::vector<std::string> failures = o.failures;
    if (!n.failure.empty()) failures.insert(failures.begin(), n.failure);
    r.verdict = Verdict::Pass;
    if (!failures.empty()) {
        r.verdict = Verdict::Fail;
        r.summary = failures.front();
        r.message = join_reasons(failures);
    } else if (!o.errors.empty()) {
        r.verdict = Verdict::Error;
        r.message = join_reasons(o.errors);
    } else if (!(n.tolerance < n.integral)) {
        // The reference is unknown within its own size: no p-value means anything.
        r.p_value.reset();
        r.verdict = Verdict::NotApplicable;
        r.summary = fmt::format("not applicable: pdf(wo, .)'s integral {:.4g} is known only within {:.3g} (its "
                                "float noise): no cell can be tested", n.integral, n.tolerance);
        r.message = r.summary.substr(std::string("not applicable: ").size()) +
                    "; the lobe is narrower than the float directions that evaluate it";
    } else {
        r.message = fmt::format("Pearson p {:.3g}, largest residual {:.3g} (p {:.3g}), landing p {:.3g}: {} of {} "
                                "non-delta draws landed, {:.6g} expected from the pdf's integral",
                                o.p_value(), local.residual, local.p_value, n.p_value, n.landed, n.trials,
                                static_cast<double>(n.trials) * n.integral / (1.0 - n.delta));
    }
}

Table draw_table(const Draws& d, const Normalisation& n) {
    Table t{"Where the draws went", {"kind", "samples", "share", "claimed or expected"}, {}};
    const double total = static_cast<double>(d.total);
    const auto row = [&](std::string kind, uint64_t count, std::string claim) {
        t.rows.push_back({std::move(kind), std::to_string(count), fmt::format("{:.6g}", static_cast<double>(count) / total),
                          std::move(claim)});
    };
    const double room = 1.0 - n.delta;
    row("continuous (landed)", n.landed, fmt::format("{:.6g} (pdf integral)", n.integral));
    row("no sample", d.no_sample, fmt::format("{:.6g} (1 - delta - integral)", room - n.integral));
    for (int k = 0; k < kDeltaLobes; ++k) {
        const DeltaTally::Lobe& l = d.delta.lobes[static_cast<std::size_t>(k)];
        if (l.count > 0) row(delta_lobe_name(k), l.count, fmt::format("{:.6g} (claimed)", l.claimed()));
    }
    return t;
}

/// The three tests the row's p-value combines, each at its share of the
/// level: Pearson's, the largest residual's, the landing share's.
void bsdf_chi2_p_lines(const CheckResult& r, double level, std::vector<JudgedQuantity>& out) {
    const auto pearson = r.figure("pearson_p_value"), local = r.figure("local_p_value"),
               landing = r.figure("landing_p_value");
    if (!pearson || !local || !landing) return;
    const double pearson_share = 1.0 - chi2::kLocalLevelShare - kLandingLevelShare;
    const auto note = [](double share) { return fmt::format(" ({:.3g} \u00d7 level)", share); };
    out.push_back(p_line(fmt::format("Pearson X\u00b2 = {:.4g} on {} dof: p-value", r.figure("statistic").value_or(NAN),
                                     judged_number(r.figure("dof").value_or(NAN))),
                         *pearson, pearson_share * level, note(pearson_share)));
    out.push_back(p_line(fmt::format("largest cell residual {:+.2f}: p-value over the cells",
                                     r.figure("local_max_residual").value_or(NAN)),
                         *local, chi2::kLocalLevelShare * level, note(chi2::kLocalLevelShare)));
    out.push_back(p_line(fmt::format("share of draws that landed ({} of {}): binomial p-value",
                                     judged_number(r.figure("continuous_samples").value_or(NAN)),
                                     judged_number(r.figure("samples").value_or(NAN) -
                                                   r.figure("delta_samples").value_or(0.0))),
                         *landing, kLandingLevelShare * level, note(kLandingLevelShare)));
}

/// pdf(wo, .)'s integral against what the continuous lobes hold.
void bsdf_chi2_bound_lines(const CheckResult& r, std::vector<JudgedQuantity>& out) {
    const auto integral = r.figure("pdf_integral"), tolerance = r.figure("integral_tolerance"),
               delta = r.figure("delta_claimed");
    if (!integral || !tolerance || !delta) return;
    const double room = 1.0 - *delta + *tolerance;
    // The margin: the excess over the continuous lobes' share, over the tolerance.
    out.push_back(with_margin(
        {"pdf(wo, .) integrated over the sphere", fmt::format("{:.9g}", *integral),
         fmt::format("\u2264 1 \u2212 {} (delta lobes) + {}", judged_number(*delta), judged_number(*tolerance)),
         *integral <= room ? JudgedQuantity::State::Within : JudgedQuantity::State::Beyond},
        std::max(0.0, *integral - (1.0 - *delta)), *tolerance));
}

/// The marks of a row's residual plots, and what fails it.
void mark_bsdf_chi2_plots(CheckResult& r) {
    mark_residual_plots(r, fmt::format("The sphere of wi in (phi_i, cos theta_i), where cell area is solid angle: cos "
                                       "theta_i > 0 on wo's side. Residual r = (observed \u2212 expected) / "
                                       "\u221aexpected per cell: noise stays within about \u00b14. The check fails when "
                                       "Pearson's p < {:.2g} \u00d7 level, the ringed largest residual's p < {:.2g} "
                                       "\u00d7 level or the landing share's p < {:.2g} \u00d7 level",
                                       1.0 - chi2::kLocalLevelShare - kLandingLevelShare, chi2::kLocalLevelShare,
                                       kLandingLevelShare));
}

class BsdfChi2Check final : public BsdfCheck {
public:
    std::string name() const override { return "bsdf_chi2"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"outside", "continuous samples off the sphere", FigureRule::Zero},
                            {"nan", "continuous samples with NaN coordinates", FigureRule::Zero},
                            {"zero_expected_hits", "continuous samples in cells where pdf(wo, .) integrates to 0",
                             FigureRule::Zero},
                            {"reintegrated_cells", "cells integrated again around samples", FigureRule::Counted}},
                .p_values = bsdf_chi2_p_lines,
                .p_value = fmt::format("p-value: min(Pearson / {:.3g}, residual / {:.3g}, landing / {:.3g}), at most 1",
                                       1.0 - chi2::kLocalLevelShare - kLandingLevelShare, chi2::kLocalLevelShare,
                                       kLandingLevelShare),
                .bounds = bsdf_chi2_bound_lines,
                .marks = mark_bsdf_chi2_plots};
    }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "The continuous lobes' wi over cells of the sphere against pdf(wo, .) (Pearson's X\u00b2 and "
                "the largest residual, with the chi2 check's float-aware cells and bands), and the share of draws "
                "that landed against pdf(wo, .)'s integral; also fails on samples where the pdf integrates to 0 and "
                "an integral above what the continuous lobes hold.",
                "min(p_X\u00b2 / 0.7, p_cell / 0.2, p_landing / 0.1), weighted Bonferroni."};
    }
    std::string description() const override {
        return "BSDF: chi-square of the continuous lobes' wi over the sphere against pdf(wo, .), and the pdf's "
               "integral against the share of draws that landed (Sidak-corrected)";
    }

protected:
    Applicability bsdf_applicability(const BsdfCase& b) const override {
        if (!has(b.claims().lobes, BsdfFlags::Continuous)) return Applicability::not_about_such_cases();
        return unless_stochastic(b, "its sampler's density is not its pdf(), whose values");
    }

    CheckResult run_bsdf(const BsdfCase& bsdf, const CheckContext& ctx) const override {
        chi2::Chi2Options options;
        options.resolution = chi2::float_aware_resolution(bsdf.domain(), bsdf_resolution(bsdf), ctx.options().samples);
        options.strict = ctx.options().strict;
        // The uniform grid, or cells of equal probability where a pilot of
        // the continuous samples fills under a quarter of it, as the chi2
        // check chooses (chi2/equal_probability.h).
        const chi2::Binning grid(bsdf.domain(), options.resolution);
        const std::vector<chi2::SamplePoint> pilot =
            continuous_pilot(bsdf, ctx, chi2::kPilotPointsPerCell * grid.cell_count());
        chi2::EqualProbabilityCells cells;
        if (chi2::effective_cells(grid, pilot) < chi2::kMinEffectiveCellShare * static_cast<double>(grid.cell_count()))
            cells = chi2::equal_probability_cells(grid, pilot, ctx.options().samples);
        const chi2::Binning binning =
            cells.edges.empty() ? grid : chi2::Binning(bsdf.domain(), grid.resolution(), cells.edges);
        options.resolution = binning.resolution();
        const Counted c = integrate_and_draw(bsdf, ctx, binning, pilot, options);
        const Draws& d = c.draws;
        const Normalisation n = normalisation(c.integrals, d, options.strict);
        chi2::Chi2Outcome o = chi2::evaluate_chi2(binning, d.hist, conditional(c.integrals), n.landed, options);
        o.reintegrated_cells = c.reintegrated_cells;
        const chi2::LocalResidual local = chi2::largest_band_residual(o, n.landed, ctx.executor());
        CheckResult r;
        add_figures(r, o, local, n, d, ctx.options(), binning);
        add_pilot_refinement_figures(r.figures, c.pilot_refinement);
        judge(r, o, local, n);
        if (r.verdict == Verdict::Pass) r.weak = weakness(r);
        r.plots.push_back(cell_heatmaps(binning, o, "wi cells of " + bsdf.name() + " (continuous lobes)"));
        r.tables.push_back(draw_table(d, n));
        r.tables.push_back(worst_cells(binning, o));
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_bsdf_chi2_check() { return std::make_unique<BsdfChi2Check>(); }

}  // namespace warpcheck::bsdf
