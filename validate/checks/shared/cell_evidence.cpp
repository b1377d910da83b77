#include "validate/checks/shared/cell_evidence.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "chi2/local_residual.h"

namespace warpcheck {
namespace {

CellAxes labels(const chi2::Binning& b, const CellAxes& axes) {
    return {axes.u.empty() ? b.u_label() : axes.u, axes.v.empty() ? b.v_label() : axes.v};
}

}  // namespace

Plot cell_heatmaps(const chi2::Binning& b, const chi2::Chi2Outcome& o, const std::string& title,
                   const CellAxes& axes) {
    const CellAxes a = labels(b, axes);
    Plot plot;
    plot.kind = Plot::Kind::Heatmaps;
    plot.title = title;
    plot.x_label = a.u;
    plot.y_label = a.v;
    chi2::ParamRect r = b.parameter_bounds();
    if (b.has_own_edges()) {
        plot.x_label = "column of equal probability in its row (" + a.u + " ascending)";
        plot.y_label = "row of equal probability (" + a.v + " ascending)";
        r = {0.0, static_cast<double>(b.cols()), 0.0, static_cast<double>(b.rows())};
    }
    const auto map = [&](std::string label, std::vector<double> values) {
        Heatmap h;
        h.label = std::move(label);
        h.rows = b.rows();
        h.cols = b.cols();
        h.x_min = r.u0;
        h.x_max = r.u1;
        h.y_min = r.v0;
        h.y_max = r.v1;
        h.values = std::move(values);
        return h;
    };
    plot.heatmaps.push_back(map("observed", std::vector<double>(o.histogram.counts.begin(), o.histogram.counts.end())));
    plot.heatmaps.push_back(map("expected", o.expected));
    Heatmap residual = map("residual (obs - exp) / sqrt(exp)", o.residual);
    residual.color_scale = Heatmap::ColorScale::Diverging;
    residual.min_color_limit = 4.0;
    plot.heatmaps.push_back(std::move(residual));
    return plot;
}

Table worst_cells(const chi2::Binning& b, const chi2::Chi2Outcome& o, const CellAxes& axes) {
    const CellAxes a = labels(b, axes);
    std::vector<std::size_t> order(b.cell_count());
    std::iota(order.begin(), order.end(), std::size_t{0});
    const auto badness = [&](std::size_t c) {
        const double res = o.residual[c];
        return std::isnan(res) ? (o.histogram.counts[c] > 0 ? HUGE_VAL : -1.0) : std::abs(res);
    };
    const std::size_t shown = std::min<std::size_t>(8, order.size());
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(shown), order.end(),
                      [&](std::size_t x, std::size_t y) {
                          const double bx = badness(x), by = badness(y);
                          return bx != by ? bx > by : x < y;
                      });
    const bool two_d = b.parameter_dimension() == 2;
    Table t{"Cells with the largest residuals", {"cell", a.u + " range"}, {}};
    if (two_d) t.columns.push_back(a.v + " range");
    for (const char* c : {"observed", "expected", "residual"}) t.columns.emplace_back(c);
    for (std::size_t k = 0; k < shown; ++k) {
        const std::size_t c = order[k];
        const chi2::ParamRect r = b.cell_rect(c);
        std::vector<std::string> row = {std::to_string(c), fmt::format("[{:.5g}, {:.5g})", r.u0, r.u1)};
        if (two_d) row.push_back(fmt::format("[{:.5g}, {:.5g})", r.v0, r.v1));
        row.push_back(std::to_string(o.histogram.counts[c]));
        row.push_back(fmt::format("{:.6g}", o.expected[c]));
        row.push_back(fmt::format("{:.3g}", o.residual[c]));
        t.rows.push_back(std::move(row));
    }
    return t;
}

void add_pilot_refinement_figures(std::vector<Figure>& figures, const chi2::PilotRefinement& p) {
    figures.push_back({"pilot_partitioned_cells", static_cast<double>(p.cells_cut)});
    figures.push_back({"pilot_corrected_cells", static_cast<double>(p.cells_changed)});
    figures.push_back({"pilot_corrected_mass", p.missed_mass});
    figures.push_back({"pilot_sharpened_cells", static_cast<double>(p.cells_sharpened)});
}

namespace {

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

void mark_heatmaps(Plot& plot, const std::optional<RingedCell>& cell, const std::optional<double>& z) {
    for (std::size_t i = 0; i < plot.heatmaps.size(); ++i) {
        const Heatmap& h = plot.heatmaps[i];
        if (!h.label.starts_with("residual") || h.cols <= 0) continue;
        if (cell && cell->index < h.values.size())
            plot.cells.push_back({i, static_cast<int>(cell->index / static_cast<std::size_t>(h.cols)),
                                  static_cast<int>(cell->index % static_cast<std::size_t>(h.cols)),
                                  residual_label(*cell)});
        if (z) plot.scale_marks.push_back({i, *z, fmt::format("|r| = {:.1f}: one cell alone fails", *z)});
    }
}

void mark_residual_points(Plot& plot, const std::optional<RingedCell>& cell, const std::optional<double>& z) {
    if (plot.series.empty() || plot.series.front().label != "residual") return;
    if (z) {
        plot.limits.push_back({false, *z, fmt::format("+{:.1f}: one cell alone fails", *z)});
        plot.limits.push_back({false, -*z, fmt::format("\u2212{:.1f}", *z)});
    }
    const Series& s = plot.series.front();
    if (cell && cell->index < s.y.size() && cell->index < s.x.size())
        plot.highlights.push_back({s.x[cell->index], s.y[cell->index], residual_label(*cell)});
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

std::optional<double> single_cell_limit(const CheckResult& r) {
    const auto cells = r.figure("cells");
    if (!r.level || !cells || !(*cells >= 1.0)) return std::nullopt;
    const double tested = *cells - r.figure("zero_expected_cells").value_or(0.0);
    const double cell_level = -std::expm1(std::log1p(-chi2::kLocalLevelShare * *r.level) / std::max(tested, 1.0));
    if (!(cell_level > 0.0 && cell_level < 1.0)) return std::nullopt;
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 100; ++i) {
        const double mid = (lo + hi) / 2;
        (std::erfc(mid / std::sqrt(2.0)) > cell_level ? lo : hi) = mid;
    }
    return lo;
}

void mark_residual_plots(CheckResult& r, const std::string& rule) {
    const std::optional<RingedCell> cell = ringed_cell(r);
    const std::optional<double> z = single_cell_limit(r);
    for (Plot& plot : r.plots) {
        if (plot.kind == Plot::Kind::Heatmaps) mark_heatmaps(plot, cell, z);
        else if (plot.kind == Plot::Kind::Points) mark_residual_points(plot, cell, z);
        else continue;
        plot.note = rule + (z ? fmt::format(": one cell alone fails beyond |r| \u2248 {:.1f} (red marks).", *z) : ".");
    }
}

}  // namespace warpcheck
