#include "validate/checks/bsdf/bsdf_evidence.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace warpcheck::bsdf {

Plot cell_heatmaps(const chi2::Binning& b, const chi2::Chi2Outcome& o, const std::string& title) {
    Plot plot;
    plot.kind = Plot::Kind::Heatmaps;
    plot.title = title;
    plot.x_label = "phi_i";
    plot.y_label = "cos theta_i";
    const chi2::ParamRect r = b.parameter_bounds();
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

Table worst_cells(const chi2::Binning& b, const chi2::Chi2Outcome& o) {
    std::vector<std::size_t> order(b.cell_count());
    std::iota(order.begin(), order.end(), std::size_t{0});
    const auto badness = [&](std::size_t c) {
        const double r = o.residual[c];
        return std::isnan(r) ? (o.histogram.counts[c] > 0 ? HUGE_VAL : -1.0) : std::abs(r);
    };
    const std::size_t shown = std::min<std::size_t>(8, order.size());
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(shown), order.end(),
                      [&](std::size_t a, std::size_t c) {
                          const double ba = badness(a), bc = badness(c);
                          return ba != bc ? ba > bc : a < c;
                      });
    Table t{"Cells with the largest residuals",
            {"cell", "phi_i range", "cos theta_i range", "observed", "expected", "residual"},
            {}};
    for (std::size_t k = 0; k < shown; ++k) {
        const std::size_t c = order[k];
        const chi2::ParamRect r = b.cell_rect(c);
        t.rows.push_back({std::to_string(c), fmt::format("[{:.5g}, {:.5g})", r.u0, r.u1),
                          fmt::format("[{:.5g}, {:.5g})", r.v0, r.v1), std::to_string(o.histogram.counts[c]),
                          fmt::format("{:.6g}", o.expected[c]), fmt::format("{:.3g}", o.residual[c])});
    }
    return t;
}

}  // namespace warpcheck::bsdf
