#include "validate/samples/sample_set.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <thread>

#include <fmt/format.h>

#include "chi2/chi2_test.h"
#include "chi2/power.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/formatting.h"
#include "validate/checks/judged.h"
#include "validate/checks/shared/line_resolution.h"
#include "validate/checks/shared/power_level.h"
#include "validate/run/runner.h"
#include "warpcheck/version.h"

namespace warpcheck {
namespace {

/// The pdf of each sample, in batches.
std::vector<double> pdf_of(const WarpCase& reference, std::span<const WarpOutput> samples) {
    std::vector<double> pdf(samples.size());
    reference.pdf(samples, pdf);
    return pdf;
}

CheckResult sample_consistency(const WarpCase& reference, std::span<const WarpOutput> samples) {
    const chi2::Domain& domain = reference.domain();
    const std::vector<double> pdf = pdf_of(reference, samples);
    Tally<std::size_t> nan, outside, bad_pdf, zero_pdf;
    uint64_t boundary_zero = 0;
    double min_pdf = HUGE_VAL, max_pdf = 0.0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const chi2::DomainPoint p = to_domain_point(samples[i]);
        if (std::isnan(p[0]) || std::isnan(p[1]) || std::isnan(p[2])) nan.add(i, i);
        else if (!domain.contains(p)) outside.add(i, i);
        else if (!std::isfinite(pdf[i]) || pdf[i] < 0.0) bad_pdf.add(i, i);
        else if (pdf[i] == 0.0 && domain.on_boundary(p)) ++boundary_zero;
        else if (pdf[i] == 0.0) zero_pdf.add(i, i);
        else min_pdf = std::min(min_pdf, pdf[i]), max_pdf = std::max(max_pdf, pdf[i]);
    }
    CheckResult r;
    r.check_name = "samples_consistency";
    r.samples = samples.size();
    r.figures = {{"nan", static_cast<double>(nan.count)},           {"outside", static_cast<double>(outside.count)},
                 {"bad_pdf", static_cast<double>(bad_pdf.count)},   {"zero_pdf", static_cast<double>(zero_pdf.count)},
                 {"boundary_zero", static_cast<double>(boundary_zero)}, {"min_pdf", min_pdf},
                 {"max_pdf", max_pdf},                              {"samples", static_cast<double>(samples.size())}};
    const int dims = domain.point_dimension();
    std::vector<std::string> failures;
    Table examples{"First sample of each violation", {"violation", "row", "sample", "pdf"}, {}};
    const auto report = [&](const Tally<std::size_t>& t, const std::string& what) {
        if (t.count == 0) return;
        failures.push_back(fmt::format("{} {}", t.count, what));
        examples.rows.push_back({what, std::to_string(*t.first), format_output(samples[*t.first], dims),
                                 fmt::format("{:.9g}", pdf[*t.first])});
    };
    report(nan, "NaN samples");
    report(outside, "samples outside " + domain.describe());
    report(bad_pdf, "samples with a NaN, infinite or negative pdf");
    report(zero_pdf, "samples with pdf 0 off the domain's boundary");
    if (!examples.rows.empty()) r.tables.push_back(std::move(examples));
    r.verdict = failures.empty() && !samples.empty() ? Verdict::Pass : Verdict::Fail;
    r.summary = failures.empty() ? fmt::format("pdf in [{:.3g}, {:.3g}], {} zero on boundary", min_pdf, max_pdf, boundary_zero)
                                 : failures.front();
    r.message = samples.empty() ? "no samples" : join_reasons(failures);
    return r;
}

Plot residual_map(const chi2::Binning& b, const chi2::Chi2Outcome& o, const std::string& name) {
    Plot plot;
    const chi2::ParamRect rect = b.parameter_bounds();
    if (b.parameter_dimension() == 2) {
        plot.kind = Plot::Kind::Heatmaps;
        Heatmap h{"residual (obs - exp) / sqrt(exp)", b.rows(), b.cols(), rect.u0, rect.u1, rect.v0, rect.v1, o.residual,
                  Heatmap::ColorScale::Diverging, 4.0};
        plot.heatmaps.push_back(std::move(h));
        plot.x_label = b.u_label();
        plot.y_label = b.v_label();
    } else {
        plot.kind = Plot::Kind::Points;
        Series s{"residual", {}, o.residual};
        for (std::size_t c = 0; c < b.cell_count(); ++c) s.x.push_back(b.cell_position(c));
        plot.series.push_back(std::move(s));
        plot.x_label = b.u_label();
        plot.y_label = "(obs - exp) / sqrt(exp)";
    }
    plot.title = "chi2 residuals of the samples against " + name;
    return plot;
}

CheckResult sample_chi2(const WarpCase& reference, std::span<const WarpOutput> samples, const RunOptions& options,
                        const chi2::ParallelFor& parallel) {
    const uint64_t n = samples.size();
    const chi2::Binning binning(reference.domain(),
                                chi2::float_aware_resolution(reference.domain(), line_resolution(reference), n));
    chi2::Chi2Options o;
    o.resolution = binning.resolution();
    o.strict = options.strict;
    const chi2::SampleChunk rows = [&](std::size_t chunk, std::span<chi2::SamplePoint> out) {
        std::copy_n(samples.begin() + static_cast<std::ptrdiff_t>(chunk * o.chunk_size), out.size(), out.begin());
    };
    const chi2::BatchPdf pdf = [&](std::span<const chi2::DomainPoint> points, std::span<double> density) {
        std::vector<WarpOutput> x(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) x[i] = to_warp_output(points[i]);
        reference.pdf(x, density);
    };
    const chi2::Chi2Outcome outcome = chi2::run_chi2_test(binning, n, rows, pdf, o, parallel);
    CheckResult r;
    r.check_name = "samples_chi2";
    r.samples = n;
    const double level = power_level(options, 1);
    const double tilt = outcome.dof() >= 1 ? chi2::pearson_tilt_for_noncentrality(
                                                 chi2::pearson_noncentrality_for_power(outcome.dof(), level), n)
                                           : std::nan("");
    r.figures = {{"statistic", outcome.statistic()},
                 {"dof", static_cast<double>(outcome.dof())},
                 {"p_value", outcome.p_value()},
                 {"integral", outcome.integrals.total},
                 {"integral_tolerance", outcome.integral_tolerance},
                 {"outside", static_cast<double>(outcome.histogram.outside)},
                 {"nan", static_cast<double>(outcome.histogram.nan)},
                 {"zero_expected_hits", static_cast<double>(outcome.zero_expected_hits)},
                 {"cells", static_cast<double>(binning.cell_count())},
                 {"power_tilt_eps", tilt},
                 {"power_level", level},
                 {"samples", static_cast<double>(n)}};
    r.summary = fmt::format("chi2 {:.1f} dof {} p {:.3g}; 90% power: tilt {:.2g}", outcome.statistic(), outcome.dof(),
                            outcome.p_value(), tilt);
    r.plots.push_back(residual_map(binning, outcome, reference.name()));
    if (!outcome.failures.empty()) {
        r.verdict = Verdict::Fail;
        r.summary = outcome.failures.front();
        r.message = join_reasons(outcome.failures);
    } else if (!outcome.errors.empty()) {
        r.verdict = Verdict::Error;
        r.message = join_reasons(outcome.errors);
    } else {
        r.verdict = Verdict::Pass;
        r.p_value = outcome.dof() >= 1 ? outcome.p_value() : std::nan("");
    }
    return r;
}

}  // namespace

std::vector<CheckResult> judge_sample_set(const WarpCase& reference, std::span<const WarpOutput> samples,
                                          const RunOptions& options, const chi2::ParallelFor& parallel) {
    std::vector<CheckResult> rows;
    const auto timed = [&](const char* check, auto&& run) {
        const auto start = std::chrono::steady_clock::now();
        CheckResult r;
        try {
            r = run();
        } catch (const std::exception& e) {
            r.verdict = Verdict::Error;
            r.summary = std::string("error: ") + e.what();
            r.message = e.what();
        }
        r.case_name = reference.name();
        r.check_name = check;
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        rows.push_back(std::move(r));
    };
    if (!reference.has_pdf() || reference.is_discrete()) {
        CheckResult r;
        r.case_name = reference.name();
        r.check_name = "samples_chi2";
        r.verdict = Verdict::NotApplicable;
        r.summary = "not applicable: the case has no pdf function of a continuous domain";
        rows.push_back(std::move(r));
        return rows;
    }
    timed("samples_consistency", [&] { return sample_consistency(reference, samples); });
    timed("samples_chi2", [&] { return sample_chi2(reference, samples, options, parallel); });
    return rows;
}

namespace {

/// The legends of the rows this room makes (Check::legend for the checks of a
/// run): what each judges and how its p-value is formed.
CheckLegend sample_row_legend(const std::string& check) {
    if (check == "samples_consistency")
        return {check, "Every sample drawn elsewhere lies in the domain with a finite, positive pdf (a pdf of 0 "
                       "exactly on the boundary is counted, not failed); no allowance for samples rounded across "
                       "the edge of a smaller support.", ""};
    if (check == "samples_chi2")
        return {check, "Pearson's X\u00b2 of the samples drawn elsewhere over cells against the case's pdf "
                       "integrated over each cell, as chi2 runs it.",
                "Pearson's p-value with the largest cell's, as chi2 forms them."};
    if (check == "ulps")
        return {check, "The same inputs through two builds: every output coordinate's distance in floats (below "
                       "the floor, in floats of the floor) within the ulps the two claim; NaN fails.", ""};
    if (check == "two_sample")
        return {check, "Two sets of independent draws from one distribution: X\u00b2 homogeneity on cells of the "
                       "pooled samples and Anderson\u2013Darling two-sample on each of the domain's parameters.",
                "1 \u2212 (1 \u2212 min p)^k, \u0160id\u00e1k over the k tests."};
    return {check, "", ""};
}

}  // namespace

RunResult run_of_rows(std::vector<CheckResult> rows, const RunOptions& options, const std::string& command) {
    RunResult run;
    run.info.tool_version = WARPCHECK_VERSION;
    run.info.command_line = command;
    run.info.seed = options.seed;
    run.info.threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    run.info.samples = options.samples;
    run.info.strict = options.strict;
    run.info.compiler = WARPCHECK_COMPILER;
    run.info.machine = machine_description();
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", &tm);
    run.info.started_at = stamp;
    run.info.samples = 0;  // the samples the rows judged, not a count drawn
    for (CheckResult& r : rows) {
        if (std::none_of(run.info.legends.begin(), run.info.legends.end(),
                         [&](const CheckLegend& l) { return l.check == r.check_name; }))
            run.info.legends.push_back(sample_row_legend(r.check_name));
        r.rerun_command = command;
        run.info.wall_seconds += r.seconds;
        run.info.samples = std::max(run.info.samples, r.samples);
    }
    run.results = std::move(rows);
    apply_multiple_test_correction(run, options.alpha);
    for (CheckResult& r : run.results) record_judgement(r, {});  // their rules: the p-value and tolerances
    return run;
}

}  // namespace warpcheck
