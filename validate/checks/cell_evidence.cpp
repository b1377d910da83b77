#include "validate/checks/cell_evidence.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>
#include <vector>

#include <fmt/format.h>

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
}

}  // namespace warpcheck
