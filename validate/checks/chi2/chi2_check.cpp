// "chi2": Pearson's chi-square goodness-of-fit test of a warp's samples against
// its own density, on the cells of chi2::Binning (see chi2/chi2_test.h).
//
// Samples come in fixed chunks of chi2::Chi2Options::chunk_size, chunk c drawn
// from ctx.chunk_rng(c), so the histogram (integer counts) and everything after
// it are bit-identical for any --threads. Quadrature splits by cell, likewise.
//
// The check sets p_value and leaves the verdict at Pass unless it found a
// failure that needs no significance level (NaN or outside samples, samples
// where the density integrates to zero, a density that does not integrate to 1,
// a non-finite statistic): the runner applies the Šidák-corrected level.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>
#include <string_view>
#include <numeric>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "chi2/chi2_test.h"
#include "chi2/equal_probability.h"
#include "chi2/local_residual.h"
#include "chi2/min_p.h"
#include "chi2/power.h"
#include "validate/api/light_case.h"
#include "validate/checks/shared/cell_evidence.h"
#include "validate/checks/shared/cell_power.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/input_chunks.h"
#include "validate/checks/shared/line_resolution.h"
#include "validate/checks/shared/power_level.h"
#include "validate/lanes/lane_sampling.h"

namespace warpcheck {
namespace {

std::vector<Plot> line_plots(const chi2::Binning& b, const chi2::Chi2Outcome& o, const std::string& case_name) {
    std::vector<double> x(b.cell_count());
    for (std::size_t c = 0; c < x.size(); ++c) x[c] = b.cell_position(c);
    Plot counts;
    counts.kind = Plot::Kind::Lines;
    counts.title = "chi2 cells of " + case_name;
    counts.x_label = b.u_label();
    counts.y_label = "samples per cell";
    counts.series.push_back({"observed", x, std::vector<double>(o.histogram.counts.begin(), o.histogram.counts.end())});
    counts.series.push_back({"expected", x, o.expected});
    Plot residual;
    residual.kind = Plot::Kind::Points;
    residual.title = "chi2 residuals of " + case_name;
    residual.x_label = b.u_label();
    residual.y_label = "(obs - exp) / sqrt(exp)";
    residual.series.push_back({"residual", x, o.residual});
    return {std::move(counts), std::move(residual)};
}

/// The compute part: samples drawn chunk by chunk, binned, and the density
/// integrated over the cells (chi2::run_chi2_test).
chi2::Chi2Outcome compute(const WarpCase& warp, const CheckContext& ctx, const chi2::Binning& binning,
                          std::span<const chi2::SamplePoint> pilot) {
    chi2::Chi2Options options;
    options.resolution = binning.resolution();
    options.strict = ctx.options().strict;
    options.pilot = pilot;
    const InputKind kind = warp.input_kind();
    const chi2::BatchPdf pdf = [&](std::span<const chi2::DomainPoint> points, std::span<double> density) {
        std::vector<WarpOutput> x(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) x[i] = to_warp_output(points[i]);
        warp.pdf(x, density);
    };
    // The same histogram, 24 samples at a time (validate/lanes/lane_sampling.h), where
    // the processor has AVX-512 or AVX2: by the warp's lane form, or else by its own
    // sample between the lanes' draws and binning. Elsewhere the scalar chunks
    // below, which beat the lanes' portable build (28-31 against 20-24 M samples/s per core).
    if (kind == InputKind::Uniform2D && binning.lane_plan() && vector_lane_path_available()) {
        const LaneSampler sampler = warp.info().lanes ? *warp.info().lanes : planar_lane_sampler(warp);
        const chi2::SampleHistogram lanes = [&](std::span<const unsigned char> zero) {
            const auto chunk_rng = [&](uint64_t chunk) {
                ctx.throw_if_cancelled();
                return ctx.chunk_rng(chunk);
            };
            return lane_histogram(binning, ctx.options().samples, options.chunk_size, chunk_rng, sampler, zero,
                                  ctx.executor());
        };
        return chi2::run_chi2_test(binning, ctx.options().samples, lanes, pdf, options, ctx.executor());
    }
    return chi2::run_chi2_test(binning, ctx.options().samples, chi2_sample_chunks(warp, ctx), pdf, options,
                               ctx.executor());
}

/// The pilot sample that places the cells (chi2/equal_probability.h):
/// chi2::kPilotPointsPerCell per cell of `grid`, whole chunks.
std::vector<chi2::SamplePoint> draw_pilot(const WarpCase& warp, const CheckContext& ctx, const chi2::Binning& grid) {
    const chi2::SampleChunk chunk = chi2_sample_chunks(warp, ctx);
    const std::size_t size = chi2::Chi2Options{}.chunk_size;
    const std::size_t chunks = (chi2::kPilotPointsPerCell * grid.cell_count() + size - 1) / size;
    std::vector<chi2::SamplePoint> pilot(chunks * size);
    ctx.parallel_for(chunks, [&](std::size_t c) {
        chunk(kPilotChunkBase + c, std::span<chi2::SamplePoint>(pilot).subspan(c * size, size));
    });
    return pilot;
}

/// The largest band relative to its cell's Poisson deviation, sqrt(E).
double band_in_sd(const chi2::Chi2Outcome& o) {
    double worst = 0.0;
    for (std::size_t i = 0; i < o.band.size(); ++i)
        if (o.expected[i] > 0.0) worst = std::max(worst, o.band[i] / std::sqrt(o.expected[i]));
    return worst;
}

/// What the row says besides the statistic: what the expected counts are
/// uncertain by, and any allowance the verdict used.
std::string notes(const chi2::Chi2Outcome& o) {
    std::string s;
    const double band = band_in_sd(o);
    // A noncentrality of 1 moves the critical value by about 1, a fiftieth of
    // the statistic's deviation at 1000 cells: below that the bands cost no
    // power worth a word; above it, say what the expected counts are uncertain by.
    if (o.pearson.noncentrality >= 1.0)
        s += fmt::format("; expected counts uncertain by up to {:.2g} sd (float resolution, quadrature): noncentrality {:.3g}",
                         band, o.pearson.noncentrality);
    if (o.float_noise_used)
        s += fmt::format("; integral {:.7g}: off 1 by the pdf's float rounding (allowance {:.2g})", o.integrals.total,
                         o.float_noise_allowance);
    if (o.reintegrated_cells > 0) s += fmt::format("; {} cells integrated again around samples", o.reintegrated_cells);
    return s;
}

/// The judge part. The rules that need no significance level (NaN or outside
/// samples, hits where the density is zero, a density that does not
/// integrate to 1 within the quadrature's verified bound and its float noise)
/// are decided by the engine and fail here, before any error (an error must
/// never hide a failure); the p-value is judged by the runner at the
/// Sidak-corrected level of the whole run (its size: the family-wise alpha).
void judge(CheckResult& r, const chi2::Chi2Outcome& o, const chi2::LocalResidual& local) {
    // Pearson's statistic and the largest cell residual, one p-value (chi2/min_p.h).
    const double local_p = local.p_value;
    if (o.dof() >= 1)
        r.p_value = chi2::weighted_min_p({o.p_value(), local_p}, {1.0 - chi2::kLocalLevelShare, chi2::kLocalLevelShare});
    r.summary = fmt::format("chi2 {:.1f} dof {} p {:.3g}; 90% power: tilt {:.2g}", o.statistic(), o.dof(),
                            o.p_value(), r.figure("power_tilt_eps").value_or(std::nan(""))) +
                notes(o);
    r.weak = weakness(r);
    if (!o.failures.empty()) {
        r.verdict = Verdict::Fail;
        r.summary = o.failures.front();
        r.message = join_reasons(o.failures);
        r.p_value.reset();  // decided without a level: no p-value line for it
    } else if (!o.errors.empty()) {
        r.verdict = Verdict::Error;
        r.message = join_reasons(o.errors);
    } else {
        r.verdict = Verdict::Pass;
    }
}

void add_figures(CheckResult& r, const chi2::Chi2Outcome& o, const chi2::LocalResidual& local,
                 const chi2::Binning& binning, const RunOptions& options) {
    const uint64_t samples = options.samples;
    r.samples = samples;
    const chi2::Histogram& h = o.histogram;
    r.figures = {
        {"statistic", o.statistic()},
        {"dof", static_cast<double>(o.dof())},
        {"p_value", o.p_value()},
        {"integral", o.integrals.total},
        {"integral_tolerance", o.integral_tolerance},
        {"integration_error", o.integrals.error_total},
        {"integration_error_ratio", o.integrals.worst_error_ratio},
        {"unconverged_cells", static_cast<double>(o.integrals.unconverged_cells)},
        {"verification_mismatches", static_cast<double>(o.integrals.verification_mismatches)},
        {"reintegrated_cells", static_cast<double>(o.reintegrated_cells)},
        {"float_noise", o.integrals.float_noise_total},
        {"float_noise_allowance", o.float_noise_allowance},
        {"edge_band", o.edge_band_total},
        {"band_max_sd", band_in_sd(o)},
        {"noncentrality", o.pearson.noncentrality},
        {"quadrature_evaluations", static_cast<double>(o.integrals.evaluations)},
        {"cells", static_cast<double>(binning.cell_count())},
        {"cells_used", static_cast<double>(o.pearson.terms)},
        {"pooled_cells", static_cast<double>(o.pearson.small_cells)},
        {"pools", static_cast<double>(o.pearson.pools)},
        {"outside", static_cast<double>(h.outside)},
        {"nan", static_cast<double>(h.nan)},
        {"zero_expected_hits", static_cast<double>(o.zero_expected_hits)},
        {"boundary_zero_density", static_cast<double>(o.boundary_hits)},
        {"zero_expected_cells", static_cast<double>(o.zero_expected_cells)},
        {"snapped_at_support_edge", static_cast<double>(h.snapped)},
        {"samples", static_cast<double>(samples)},
        {"equal_probability_cells", binning.has_own_edges() ? 1.0 : 0.0},
        {"rows", static_cast<double>(binning.rows())},
        {"columns", static_cast<double>(binning.cols())},
    };
    if (binning.domain().unbounded_line())
        r.figures.push_back({"half_line_scale", binning.resolution().half_line_scale});
    if (binning.domain().is<chi2::RealLine>())
        r.figures.push_back({"line_center", binning.resolution().line_center});
    // The localised statistic (chi2/local_residual.h) and the stated power of
    // the test as it ran (validate/checks/shared/cell_power.h), at the planned level
    // less the largest residual's share.
    r.figures.insert(r.figures.end(), {{"local_max_residual", local.residual},
                                       {"local_cell", static_cast<double>(local.cell)},
                                       {"local_p_value", local.p_value}});
    add_cell_power(r, binning, o, (1.0 - chi2::kLocalLevelShare) * power_level(options, 1), samples);
}

/// The evidence part: heatmaps (2D) or count and residual curves (1D), and the
/// cells that deviate most.
void add_plots(CheckResult& r, const chi2::Chi2Outcome& o, const chi2::Binning& binning, const std::string& name) {
    if (binning.parameter_dimension() == 2) {
        r.plots.push_back(cell_heatmaps(binning, o, "chi2 cells of " + name));
    } else {
        for (Plot& p : line_plots(binning, o, name)) r.plots.push_back(std::move(p));
    }
    r.tables.push_back(worst_cells(binning, o));
}

/// The two tests the row's p-value combines, each at its share of the level
/// (as run_chi2_on_cells weighs them: weighted_min_p).
void chi2_p_lines(const CheckResult& r, double level, std::vector<JudgedQuantity>& out) {
    const auto pearson = r.figure("p_value"), local = r.figure("local_p_value");
    if (!pearson || !local) return;
    const double share = chi2::kLocalLevelShare;
    out.push_back(p_line(fmt::format("Pearson X\u00b2 = {:.4g} on {} dof: p-value", r.figure("statistic").value_or(NAN),
                                     judged_number(r.figure("dof").value_or(NAN))),
                         *pearson, (1.0 - share) * level, fmt::format(" ({:.3g} \u00d7 level)", 1.0 - share)));
    out.push_back(p_line(fmt::format("largest cell residual {:+.2f} (cell {}): p-value over the cells",
                                     r.figure("local_max_residual").value_or(NAN),
                                     judged_number(r.figure("local_cell").value_or(NAN))),
                         *local, share * level, fmt::format(" ({:.3g} \u00d7 level)", share)));
}

/// The marks of a row's residual plots, and what fails it.
void mark_chi2_plots(CheckResult& r) {
    mark_residual_plots(r, fmt::format("Residual r = (observed \u2212 expected) / \u221aexpected per cell: noise stays "
                                       "within about \u00b14. The check fails when Pearson's p < {:.2g} \u00d7 level or "
                                       "the ringed largest residual's p < {:.2g} \u00d7 level",
                                       1.0 - chi2::kLocalLevelShare, chi2::kLocalLevelShare));
}

class Chi2Check final : public Check {
public:
    std::string name() const override { return "chi2"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"integral", "integral of the density over the domain", FigureRule::WithinOfOne,
                             "integral_tolerance"},
                            {"outside", "samples outside the domain", FigureRule::Zero},
                            {"nan", "samples with NaN coordinates", FigureRule::Zero},
                            {"zero_expected_hits", "samples in cells of expected count 0", FigureRule::Zero},
                            {"pooled_cells", "cells pooled (expected count below 5)", FigureRule::Counted}},
                .p_values = chi2_p_lines,
                .p_value = fmt::format("p-value: min(Pearson / {:.3g}, residual / {:.3g}), at most 1",
                                       1.0 - chi2::kLocalLevelShare, chi2::kLocalLevelShare),
                .marks = mark_chi2_plots};
    }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "Pearson's X\u00b2 of the samples over cells against the pdf integrated over each cell "
                "(cells expected below 5 pooled), and the single cell least likely under the model; also fails on "
                "samples outside the domain, NaN samples, samples where the density is 0, and an integral off 1 "
                "beyond its tolerance.",
                "min(p_X\u00b2 / 0.8, p_cell / 0.2), weighted Bonferroni: Pearson gets 80% of the level, the largest "
                "residual (its exact binomial p, \u0160id\u00e1k over the cells) 20%. The summary's p is Pearson's "
                "alone."};
    }
    std::string description() const override {
        return "Pearson chi-square test of the samples against the pdf integrated over cells (pooled, Sidak-corrected)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        // An MIS case's one-sample model has no density of total mass 1 where
        // a strategy declines (a shadowed microfacet sample), and this test
        // has no cell for the missing mass; each strategy's distribution is
        // its own case's test (a light's chi2, a BSDF's bsdf_chi2), and
        // mis_weights and mis_estimator test how they combine.
        if (as_mis(warp) != nullptr)
            return Applicability::lacks("an MIS case's strategies are tested as their own cases; mis_weights and "
                                        "mis_estimator test how they combine");
        return Applicability::when(warp.has_pdf() && !warp.is_discrete());
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        // The uniform grid, or where a pilot sample uses less than half its
        // cells, cells of equal probability placed by the pilot on the grid's
        // counts (chi2/equal_probability.h).
        const chi2::Binning grid(warp.domain(), chi2::float_aware_resolution(warp.domain(), line_resolution(warp),
                                                                            ctx.options().samples));
        const std::vector<chi2::SamplePoint> pilot = draw_pilot(warp, ctx, grid);
        const double effective = chi2::effective_cells(grid, pilot);
        chi2::EqualProbabilityCells cells;
        if (effective < chi2::kMinEffectiveCellShare * static_cast<double>(grid.cell_count()))
            cells = chi2::equal_probability_cells(grid, pilot, ctx.options().samples);
        const chi2::Binning binning =
            cells.edges.empty() ? grid : chi2::Binning(warp.domain(), grid.resolution(), cells.edges);
        const chi2::Chi2Outcome outcome = compute(warp, ctx, binning, pilot);
        CheckResult r;
        const chi2::LocalResidual local = chi2::largest_band_residual(outcome, ctx.options().samples, ctx.executor());
        add_figures(r, outcome, local, binning, ctx.options());
        add_pilot_refinement_figures(r.figures, outcome.pilot_refinement);
        r.figures.insert(r.figures.end(), {{"pilot_effective_cells", effective},
                                           {"pilot_samples_used", static_cast<double>(cells.pilot_used)},
                                           {"rows_merged", static_cast<double>(cells.rows_merged)},
                                           {"column_halvings", static_cast<double>(cells.column_halvings)}});
        judge(r, outcome, local);
        add_plots(r, outcome, binning, warp.name());
        r.phases = {{"integration", outcome.integration_seconds},
                    {"sampling+binning", outcome.sampling_seconds},
                    {"statistics", outcome.statistics_seconds}};
        return r;
    }
};

}  // namespace

chi2::SampleChunk chi2_sample_chunks(const WarpCase& warp, const CheckContext& ctx) {
    return [&warp, &ctx](std::size_t chunk, std::span<chi2::SamplePoint> out) {
        ctx.throw_if_cancelled();
        std::vector<WarpInput> inputs(out.size());
        Pcg32 rng = ctx.chunk_rng(chunk);
        draw_inputs(rng, warp.input_kind(), inputs);
        warp.sample(inputs, out);
    };
}

std::unique_ptr<Check> make_chi2_check() { return std::make_unique<Chi2Check>(); }

const char* chi2_vector_path() {
    return vector_lane_path_available() ? lane_path_name(auto_lane_path()) : "scalar";
}

}  // namespace warpcheck
