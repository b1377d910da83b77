// What the report draws into a check's plots, so that each shows the quantity
// judged and its limit: the round trip's tolerance, the points that decide the
// unbinned statistics (bsdf_unbinned's too), the floats an exhaustive sweep
// found wrong, the cell with the largest chi-square residual and the residual
// at which one cell alone would fail (bsdf_chi2's map of the sphere too).
// Read from the result's figures, tables and series.
#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "reports/html_report_parts.h"
#include "reports/text.h"

namespace warpcheck::html {
namespace {


std::string short_number(double v) { return std::isfinite(v) ? fmt::format("{:.3g}", v) : format_number(v); }

// ---- roundtrip --------------------------------------------------------------

/// The bar of decade d (errors in [10^d, 10^(d+1))) stands at x = d, so an
/// error e lies at log10(e) - 1/2 in the bar's slot [d - 1/2, d + 1/2).
void annotate_roundtrip(const CheckResult& r, const Plot& plot, SvgOptions& options) {
    const auto tolerance = r.figure("tolerance");
    if (plot.kind != Plot::Kind::Bars || !tolerance || !(*tolerance > 0.0)) return;
    options.limits.push_back({true, std::log10(*tolerance) - 0.5, "tolerance " + short_number(*tolerance)});
}

// ---- unbinned ---------------------------------------------------------------

const Series* series_labelled(const Plot& plot, const std::string& label) {
    for (const Series& s : plot.series)
        if (s.label == label && s.x.size() == s.y.size() && !s.x.empty()) return &s;
    return nullptr;
}

/// Kuiper's V = D+ + D-: its two excursions, the highest and lowest points of
/// sqrt(n) (F_n - F).
void mark_kuiper(const Series& s, SvgOptions& options) {
    const auto [lo, hi] = std::minmax_element(s.y.begin(), s.y.end());
    const auto x_of = [&](auto it) { return s.x[static_cast<std::size_t>(it - s.y.begin())]; };
    options.highlights.push_back({x_of(hi), *hi, s.label + ": D\u207a"});
    options.highlights.push_back({x_of(lo), *lo, s.label + ": D\u207b"});
}

/// Anderson-Darling's A^2 integrates n (F_n - F)^2 / (F (1 - F)) over F: its
/// largest term, often in a tail where the curve itself looks small.
void mark_anderson_darling(const Series& s, SvgOptions& options) {
    double best = -1.0;
    std::size_t at = 0;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
        const double f = s.x[i];
        if (!(f > 0.0 && f < 1.0) || !std::isfinite(s.y[i])) continue;
        const double term = s.y[i] * s.y[i] / (f * (1.0 - f));
        if (term > best) best = term, at = i;
    }
    if (best >= 0.0) options.highlights.push_back({s.x[at], s.y[at], s.label + ": largest A\u00b2 term"});
}

void annotate_unbinned(const CheckResult& r, const Plot& plot, SvgOptions& options) {
    if (plot.kind != Plot::Kind::Lines) return;
    for (const auto& [marginal, test] : judged_unbinned_tests(r)) {
        const Series* s = series_labelled(plot, marginal);
        if (!s) continue;
        if (test == "kuiper") mark_kuiper(*s, options);
        if (test == "ad") mark_anderson_darling(*s, options);
    }
}

// ---- chi2 -------------------------------------------------------------------

/// The |residual| at which one cell alone fails, in the normal approximation
/// of its binomial count: two-sided p = erfc(z / sqrt 2) at the cell level
/// 1 - (1 - share * level)^(1 / cells). For the note and the marks only; the
/// check judges the exact binomial p-value.
std::optional<double> single_cell_limit(const CheckResult& r) {
    const auto cells = r.figure("cells");
    if (!r.level || !cells || !(*cells >= 1.0)) return std::nullopt;
    const double tested = *cells - r.figure("zero_expected_cells").value_or(0.0);
    const double cell_level = -std::expm1(std::log1p(-kChi2LocalShare * *r.level) / std::max(tested, 1.0));
    if (!(cell_level > 0.0 && cell_level < 1.0)) return std::nullopt;
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 100; ++i) {
        const double mid = (lo + hi) / 2;
        (std::erfc(mid / std::sqrt(2.0)) > cell_level ? lo : hi) = mid;
    }
    return lo;
}

std::optional<std::size_t> local_cell(const CheckResult& r) {
    const auto cell = r.figure("local_cell");
    if (!cell || !(*cell >= 0.0) || *cell != std::floor(*cell)) return std::nullopt;
    return static_cast<std::size_t>(*cell);
}

/// The residuals a chi-square row plots, one per cell: its residual heatmap's
/// values, or its residual series' y. Empty if it plots none.
std::span<const double> plotted_residuals(const CheckResult& r) {
    for (const Plot& plot : r.plots) {
        for (const Heatmap& h : plot.heatmaps)
            if (h.label.starts_with("residual")) return h.values;
        if (plot.kind == Plot::Kind::Points && !plot.series.empty() && plot.series.front().label == "residual")
            return plot.series.front().y;
    }
    return {};
}

std::string residual_label(const RingedCell& cell) { return fmt::format("largest |r|: {:+.2f}", cell.residual); }

void annotate_chi2_heatmaps(const CheckResult& r, const Plot& plot, SvgOptions& options) {
    const auto cell = ringed_cell(r);
    for (std::size_t i = 0; i < plot.heatmaps.size(); ++i) {
        const Heatmap& h = plot.heatmaps[i];
        if (!h.label.starts_with("residual") || h.cols <= 0) continue;
        if (cell && cell->index < h.values.size())
            options.cells.push_back({i, static_cast<int>(cell->index / static_cast<std::size_t>(h.cols)),
                                     static_cast<int>(cell->index % static_cast<std::size_t>(h.cols)),
                                     residual_label(*cell)});
        if (const auto z = single_cell_limit(r))
            options.scale_marks.push_back({i, *z, fmt::format("|r| = {:.1f}: one cell alone fails", *z)});
    }
}

void annotate_chi2_residuals(const CheckResult& r, const Plot& plot, SvgOptions& options) {
    if (plot.series.empty()) return;
    if (const auto z = single_cell_limit(r)) {
        options.limits.push_back({false, *z, fmt::format("+{:.1f}: one cell alone fails", *z)});
        options.limits.push_back({false, -*z, fmt::format("\u2212{:.1f}", *z)});
    }
    const Series& s = plot.series.front();
    const auto cell = ringed_cell(r);
    if (cell && cell->index < s.y.size() && cell->index < s.x.size())
        options.highlights.push_back({s.x[cell->index], s.y[cell->index], residual_label(*cell)});
}

// ---- exhaustive -------------------------------------------------------------

/// The plot's x: the binade exponent e of [2^e, 2^(e+1)), -127 for denormals and 0.
double binade_of(double v) {
    const double a = std::abs(v);
    if (!(a >= 0x1p-126)) return -127.0;
    return std::floor(std::log2(a));
}

void annotate_exhaustive(const CheckResult& r, const Plot& plot, SvgOptions& options) {
    if (plot.kind != Plot::Kind::Lines) return;
    const auto value = r.figure("most_biased_float"), count = r.figure("most_biased_count");
    if (value && count && *count > 0.0)
        options.highlights.push_back({binade_of(*value), *count,
                                      fmt::format("most biased: {:.9g} \u00d7{} (ideal {})", *value, format_number(*count),
                                                  short_number(r.figure("most_biased_ideal").value_or(NAN)))});
    for (const Table& t : r.tables) {
        if (!t.title.starts_with("Outputs outside")) continue;
        for (std::size_t i = 0; i < t.rows.size() && i < 3; ++i) {
            if (t.rows[i].size() < 2) continue;
            const double v = std::strtod(t.rows[i][0].c_str(), nullptr), inputs = std::strtod(t.rows[i][1].c_str(), nullptr);
            if (std::isfinite(v) && inputs > 0)
                options.highlights.push_back({binade_of(v), inputs, fmt::format("outside [a, b): {:.9g} \u00d7{}", v, t.rows[i][1])});
        }
    }
}

}  // namespace

std::optional<RingedCell> ringed_cell(const CheckResult& r) {
    const auto cell = local_cell(r);
    if (!cell) return std::nullopt;
    RingedCell ringed{*cell, r.figure("local_max_residual").value_or(NAN)};
    if (r.figure("local_p_value") != 0.0) return ringed;
    // Underflowed: the tie among the cells at p = 0 goes to the largest |residual|.
    const std::span<const double> residuals = plotted_residuals(r);
    for (std::size_t c = 0; c < residuals.size(); ++c)
        if (std::abs(residuals[c]) > std::abs(ringed.residual) || (c == ringed.index && std::isnan(ringed.residual)))
            ringed = {c, residuals[c]};
    return ringed;
}

void annotate_plot(const CheckResult& r, std::size_t index, SvgOptions& options) {
    if (index >= r.plots.size()) return;
    const Plot& plot = r.plots[index];
    if (r.check_name == "roundtrip") annotate_roundtrip(r, plot, options);
    if (r.check_name == "unbinned" || r.check_name == "bsdf_unbinned") annotate_unbinned(r, plot, options);
    if (r.check_name == "exhaustive") annotate_exhaustive(r, plot, options);
    if ((r.check_name == "chi2" || r.check_name == "bsdf_chi2") && plot.kind == Plot::Kind::Heatmaps)
        annotate_chi2_heatmaps(r, plot, options);
    if (r.check_name == "chi2" && plot.kind == Plot::Kind::Points) annotate_chi2_residuals(r, plot, options);
}

std::string plot_note(const CheckResult& r, std::size_t index) {
    if (index >= r.plots.size()) return "";
    const Plot& plot = r.plots[index];
    if (r.check_name == "roundtrip" && plot.kind == Plot::Kind::Bars && r.figure("tolerance").value_or(0.0) > 0.0)
        return "Each bar counts the inputs whose error lies in one decade [10^e, 10^(e+1)), drawn at e; the dashed line "
               "stands at the tolerance's place in its decade. Right of it: inputs that missed the tolerance, failures "
               "unless excused (counted in the Judged table).";
    if ((r.check_name == "unbinned" || r.check_name == "bsdf_unbinned") && plot.kind == Plot::Kind::Lines)
        return "Judged per marginal: Anderson\u2013Darling's A\u00b2 (the integral of the squared curve over "
               "F(1 \u2212 F); its largest term is ringed), and on an azimuth Kuiper's V = D\u207a + D\u207b too (the "
               "ringed highest and lowest points). The \u00b1KS lines are for scale: KS is not judged.";
    if (r.check_name == "chi2" && (plot.kind == Plot::Kind::Heatmaps || plot.kind == Plot::Kind::Points)) {
        const auto z = single_cell_limit(r);
        return fmt::format("Residual r = (observed \u2212 expected) / \u221aexpected per cell: noise stays within about \u00b14. "
                           "The check fails when Pearson's p < 0.8 \u00d7 level or the ringed largest residual's p < 0.2 \u00d7 "
                           "level{}.",
                           z ? fmt::format(": one cell alone fails beyond |r| \u2248 {:.1f} (red marks)", *z) : "");
    }
    if (r.check_name == "bsdf_chi2" && plot.kind == Plot::Kind::Heatmaps) {
        const auto z = single_cell_limit(r);
        return fmt::format("The sphere of wi in (phi_i, cos theta_i), where cell area is solid angle: cos theta_i > 0 "
                           "on wo's side. Residual r = (observed \u2212 expected) / \u221aexpected per cell: noise stays "
                           "within about \u00b14. The check fails when Pearson's p < 0.7 \u00d7 level, the ringed "
                           "largest residual's p < 0.2 \u00d7 level or the landing share's p < 0.1 \u00d7 level{}.",
                           z ? fmt::format(": one cell alone fails beyond |r| \u2248 {:.1f} (red marks)", *z) : "");
    }
    if (r.check_name == "exhaustive" && plot.kind == Plot::Kind::Lines)
        return "Inputs per float, per binade: min, ideal and max. Ringed: the most biased float and any output outside "
               "[a, b) (at its binade). Outside outputs, steps down of a monotone sampler and a short reach fail; bias "
               "is reported.";
    return "";
}

}  // namespace warpcheck::html
