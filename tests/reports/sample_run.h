// A synthetic run for the report tests: one passing and one failing result with
// figures, plots and tables, plus the shapes other checks produce (exhaustive
// binade counts, tabulated curves, an error), and names full of characters
// that must be escaped.
#pragma once

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "reports/result.h"

namespace warpcheck::testing {

/// A passing round trip: an error histogram on log axes and the worst inputs.
inline CheckResult sample_roundtrip_pass() {
    CheckResult r;
    r.case_name = "uniform_cone[cos_theta_max=0.3]";
    r.check_name = "roundtrip";
    r.verdict = Verdict::Pass;
    r.summary = "max |du| 5.96e-08";
    r.figures = {{"max_error", 5.96e-08}, {"mean_error", 1.1e-08}, {"tolerance", 1e-5}, {"inputs", 100000}};
    // Its judged line, with the margin the reports read (validate/checks/judged.h).
    r.judged = {{"largest |invert(sample(u)) \u2212 u|", "5.96e-08", "\u2264 1e-05", JudgedQuantity::State::Within,
                 JudgedQuantity::Margin::OfLimit, 5.96e-08 / 1e-5}};
    r.samples = 100000;
    r.seconds = 0.042;
    r.stream_seed = 0x853c49e6748fea9bULL;
    r.stream_sequence = 0xda3e39cb94b95bdbULL;
    r.rerun_command = "validate --case 'uniform_cone[cos_theta_max=0.3]' --check roundtrip --seed 1";
    Plot errors;
    errors.kind = Plot::Kind::Bars;
    errors.title = "Round-trip error |u - invert(sample(u))|";
    errors.x_label = "error";
    errors.y_label = "inputs";
    errors.log_x = true;
    errors.log_y = true;
    Series s{"inputs", {}, {}};
    for (int e = -12; e <= -7; ++e) {
        s.x.push_back(std::pow(10.0, e));
        s.y.push_back(std::round(40000.0 * std::exp(-0.5 * (e + 9.5) * (e + 9.5))));
    }
    errors.series.push_back(s);
    r.plots.push_back(errors);
    r.tables.push_back({"Worst inputs", {"u0", "u1", "|du|"}, {{"0.999999", "0.5", "5.96e-08"}, {"0.25", "1e-07", "4.1e-08"}}});
    return r;
}

/// A failing chi-square test on the sphere: observed, expected and residual
/// heatmaps (with pooled cells) and a 1D marginal as bars.
inline CheckResult sample_chi2_fail(int rows = 16, int cols = 32) {
    CheckResult r;
    r.case_name = "trowbridge_reitz_visible[ax=0.3,ay=0.15,theta_o=60]";
    r.check_name = "chi2";
    r.verdict = Verdict::Fail;
    r.summary = "p 3.1e-12 < 7.2e-05";
    r.message = "chi-square statistic 1.45e+03 with 498 degrees of freedom: p = 3.1e-12 is below the level 7.2e-05";
    r.p_value = 3.1e-12;
    r.level = 7.2e-05;
    r.figures = {{"statistic", 1452.3}, {"dof", 498}, {"p_value", 3.1e-12}, {"pooled_cells", 14}, {"integral", 1.0213}};
    r.samples = 1000000;
    r.seconds = 1.73;
    r.stream_seed = 42;
    r.stream_sequence = 7;
    r.rerun_command = "validate --case 'trowbridge_reitz_visible[ax=0.3,ay=0.15,theta_o=60]' --check chi2 --seed 1";
    Heatmap observed{"observed", rows, cols, 0.0, 2 * std::numbers::pi, -1.0, 1.0, {}};
    Heatmap expected = observed;
    expected.label = "expected";
    Heatmap residual = observed;
    residual.label = "(obs - exp) / sqrt(exp)";
    residual.color_scale = Heatmap::ColorScale::Diverging;
    residual.min_color_limit = 4.0;
    const double n = 1e6 / (rows * cols);
    for (int i = 0; i < rows; ++i) {
        for (int j = 0; j < cols; ++j) {
            const double z = -1.0 + (i + 0.5) * 2.0 / rows, phi = (j + 0.5) * 2 * std::numbers::pi / cols;
            const double e = z < 0 ? 0.0 : n * 2.0 * z * (1.0 + 0.3 * std::cos(phi));
            const double o = z < 0 ? 0.0 : e * (1.0 + 0.15 * std::sin(2 * phi) * z) + 3.0 * std::sin(i * 7.0 + j * 3.0);
            const bool pooled = z > 0 && z < 0.15;
            const double nan = std::numeric_limits<double>::quiet_NaN();
            observed.values.push_back(o);
            expected.values.push_back(e);
            residual.values.push_back(pooled || e <= 0 ? nan : (o - e) / std::sqrt(e));
        }
    }
    Plot maps;
    maps.kind = Plot::Kind::Heatmaps;
    maps.title = "Observed and expected counts per cell";
    maps.x_label = "phi";
    maps.y_label = "cos theta";
    maps.heatmaps = {observed, expected, residual};
    r.plots.push_back(maps);

    Plot marginal;
    marginal.kind = Plot::Kind::Bars;
    marginal.title = "Marginal in cos theta";
    marginal.x_label = "cos theta";
    marginal.y_label = "samples";
    Series obs{"observed", {}, {}}, exp{"expected", {}, {}};
    for (int i = 0; i < 40; ++i) {
        const double z = (i + 0.5) / 40.0;
        obs.x.push_back(z), exp.x.push_back(z);
        exp.y.push_back(50000.0 * z);
        obs.y.push_back(50000.0 * z * (1.0 + 0.1 * std::sin(6 * z)));
    }
    marginal.series = {obs, exp};
    r.plots.push_back(marginal);
    return r;
}

/// An unbinned row at the per-test `level`: Kuiper judges phi,
/// Anderson-Darling cos theta, and the curves of sqrt(n) (F_n - F) have their
/// excursions at F = 0.3 and 0.7 (phi) and 0.02 and 0.5 (cos theta).
inline CheckResult sample_unbinned_pass(double level) {
    CheckResult r;
    r.case_name = "cosine_hemisphere";
    r.check_name = "unbinned";
    r.verdict = Verdict::Pass;
    r.summary = "key figure";
    r.p_value = -std::expm1(2.0 * std::log1p(-0.01));
    r.level = level;
    r.figures = {{"p_value", *r.p_value},          {"tests", 2},
                 {"phi_kuiper_statistic", 0.0012}, {"phi_kuiper_p_value", 0.53},
                 {"phi_ad_statistic", 0.97},       {"phi_ad_p_value", 0.37},
                 {"cos_theta_ad_statistic", 6.65}, {"cos_theta_ad_p_value", 0.01}};
    r.tables = {{"Unbinned tests per marginal", {"marginal", "test", "judged", "statistic", "p-value"},
                 {{"phi", "kuiper", "yes", "0.0012", "0.53"}, {"phi", "ad", "no", "0.97", "0.37"},
                  {"cos theta", "ad", "yes", "6.65", "0.01"}}}};
    Plot curves;
    curves.kind = Plot::Kind::Lines;
    Series phi{"phi", {}, {}}, cos_theta{"cos theta", {}, {}};
    for (int i = 1; i < 100; ++i) {
        const double f = i / 100.0;
        phi.x.push_back(f), cos_theta.x.push_back(f);
        phi.y.push_back(i == 30 ? 1.5 : i == 70 ? -1.1 : 0.1 * std::sin(i));
        cos_theta.y.push_back(i == 2 ? 0.4 : i == 50 ? 0.9 : 0.05);  // 0.4 at F = 0.02 weighs 8x more than 0.9 at 0.5
    }
    curves.series = {phi, cos_theta, {"KS critical", {0.0, 1.0}, {2.3, 2.3}}};
    r.plots = {curves};
    return r;
}

/// Exhaustive float-histogram counts: multiplicity per binade on a log scale.
inline CheckResult sample_exhaustive_pass() {
    CheckResult r;
    r.case_name = "uniform_float[bits=32]";
    r.check_name = "exhaustive";
    r.verdict = Verdict::Pass;
    r.summary = "bias 0 of 2^32 inputs";
    r.figures = {{"distinct", 1065353216}, {"out_of_range", 0}, {"inputs", 4294967296.0}};
    r.samples = 4294967296ULL;
    r.seconds = 12.5;
    r.rerun_command = "validate --case 'uniform_float[bits=32]' --check exhaustive --exhaustive";
    Plot p;
    p.kind = Plot::Kind::Lines;
    p.title = "Inputs per float, per binade";
    p.x_label = "binade exponent e ([2^e, 2^(e+1)); -127: denormals; negative side mirrored below)";
    p.y_label = "inputs per float";
    p.log_y = true;
    Series lo{"min", {}, {}}, ideal{"ideal", {}, {}}, hi{"max", {}, {}};
    for (int e = -32; e <= -1; ++e) {
        const double v = std::pow(2.0, 32 + e - 23);
        lo.x.push_back(e), ideal.x.push_back(e), hi.x.push_back(e);
        ideal.y.push_back(std::max(v, 0.0));
        lo.y.push_back(std::floor(v));
        hi.y.push_back(std::ceil(v) + (e == -1 ? 1 : 0));
    }
    p.series = {lo, ideal, hi};
    r.plots.push_back(p);
    return r;
}

/// A tabulated comparison: analytic and tabulated curves, and their difference.
inline CheckResult sample_tabulated_pass() {
    CheckResult r;
    r.case_name = "piecewise_constant_1d[n=64]";
    r.check_name = "tabulated";
    r.verdict = Verdict::Pass;
    r.summary = "max |diff| 2.4e-07";
    r.figures = {{"max_difference", 2.4e-07}, {"tolerance", 1e-06}};
    r.seconds = 0.003;
    Plot curves;
    curves.title = "Density: analytic and tabulated";
    curves.x_label = "x";
    curves.y_label = "pdf";
    Plot diff;
    diff.title = "Difference (tabulated - analytic)";
    diff.x_label = "x";
    diff.y_label = "difference";
    Series a{"analytic", {}, {}}, t{"tabulated", {}, {}}, d{"tabulated - analytic", {}, {}};
    for (int i = 0; i <= 400; ++i) {
        const double x = i / 400.0;
        const double f = 1.0 + 0.5 * std::sin(2 * std::numbers::pi * x);
        const double g = 1.0 + 0.5 * std::sin(2 * std::numbers::pi * (std::floor(x * 64) + 0.5) / 64);
        a.x.push_back(x), t.x.push_back(x), d.x.push_back(x);
        a.y.push_back(f), t.y.push_back(g), d.y.push_back(g - f);
    }
    curves.series = {a, t};
    diff.series = {d};
    r.plots = {curves, diff};
    return r;
}

/// An error: the check could not run; the name needs escaping everywhere.
inline CheckResult sample_error() {
    CheckResult r;
    r.case_name = "evil<case>&[a=1,b=\"2\",c='3']";
    r.check_name = "consistency";
    r.verdict = Verdict::Error;
    r.summary = "threw";
    r.message = "sample() threw std::domain_error: alpha <= 0 & \"quoted\" <script>alert(1)</script>";
    r.figures = {{"nan_figure", std::numeric_limits<double>::quiet_NaN()},
                 {"inf_figure", std::numeric_limits<double>::infinity()}};
    r.p_value = std::numeric_limits<double>::quiet_NaN();
    return r;
}

inline RunInfo sample_info() {
    RunInfo info;
    info.tool_version = "0.1.0";
    info.command_line = "validate --all --report report.html --seed 1";
    info.seed = 1;
    info.threads = 2;
    info.samples = 1000000;
    info.family_alpha = 0.01;
    info.per_test_alpha = 7.18e-05;
    info.statistical_tests = 140;
    info.wall_seconds = 14.2;
    info.compiler = "GCC 12.2.0";
    info.machine = "x86_64 Linux, 2 threads";
    info.started_at = "2024-05-01T12:00:00Z";
    return info;
}

/// A BSDF's albedo row at one outgoing direction of its grid, with its points
/// on the family's plots across the grid (the mean weight with its interval,
/// the albedo and its bound; their difference), as bsdf_albedo writes them.
inline CheckResult sample_bsdf_albedo(double alpha, double theta_o, double albedo, double mean, double standard_error) {
    CheckResult r;
    const std::string group = alpha == 0.05 ? "alpha=0.05" : "alpha=0.3";
    r.case_name = "rough_conductor[" + group + ",theta_o=" + std::to_string(static_cast<int>(theta_o)) + "]";
    r.check_name = "bsdf_albedo";
    r.verdict = Verdict::Pass;
    r.summary = "mean weight vs albedo";
    r.p_value = 0.4;
    r.level = 7.28e-05;
    r.figures = {{"mean_weight", mean}, {"albedo", albedo}, {"standard_error", standard_error},
                 {"energy_albedo", albedo}, {"energy_tolerance", 1e-6}};
    const double half = 2.576 * standard_error;
    FamilyPoint a{"rough_conductor", "albedo against theta_o", "theta_o (degrees)", "albedo", false, group, theta_o,
                  {{"mean weight (99% interval)", mean, mean - half, mean + half}, {"albedo", albedo}}};
    a.limits = {{"energy bound", 1.0}};
    FamilyPoint d{"rough_conductor", "mean weight minus albedo against theta_o", "theta_o (degrees)",
                  "mean weight - albedo", false, group, theta_o,
                  {{"mean weight - albedo (99% interval)", mean - albedo, mean - albedo - half, mean - albedo + half}}};
    d.limits = {{"agreement", 0.0}};
    r.family_points = {a, d};
    return r;
}

/// A rough conductor's albedo rows over its grid: two roughnesses, three
/// outgoing directions, listed out of order.
inline std::vector<CheckResult> sample_bsdf_family() {
    return {sample_bsdf_albedo(0.3, 60, 0.756, 0.7567, 3.1e-4), sample_bsdf_albedo(0.3, 0, 0.81, 0.8099, 2.4e-4),
            sample_bsdf_albedo(0.3, 85, 0.831, 0.8314, 5.2e-4), sample_bsdf_albedo(0.05, 85, 0.858, 0.8584, 3.8e-4),
            sample_bsdf_albedo(0.05, 0, 0.921, 0.9209, 1.1e-4), sample_bsdf_albedo(0.05, 60, 0.912, 0.912, 1.9e-4)};
}

/// One passing and one failing result.
inline RunResult sample_pass_and_fail() {
    RunResult run;
    run.info = sample_info();
    run.results = {sample_roundtrip_pass(), sample_chi2_fail()};
    return run;
}

/// Every shape of result, for the screenshot.
inline RunResult sample_everything() {
    RunResult run;
    run.info = sample_info();
    run.results = {sample_roundtrip_pass(), sample_chi2_fail(32, 64), sample_exhaustive_pass(), sample_tabulated_pass(),
                   sample_error()};
    return run;
}

}  // namespace warpcheck::testing
