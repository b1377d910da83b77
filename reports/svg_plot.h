// Plots of the result model (reports/result.h) as inline SVG, for the HTML
// report: line, bar and point plots with axes, ticks, legends, log scales and
// error bars (Series::y_low, y_high); heatmaps side by side with shared colour
// scales and a legend.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "reports/result.h"

namespace warpcheck {

/// A limit drawn across an x-y plot: a vertical line at x = value, or a
/// horizontal one at y = value, dashed in the colour of failures and labelled
/// (e.g. "tolerance 1.5e-05"). The axis widens to show it.
struct LimitLine {
    bool vertical = true;
    double value = 0.0;
    std::string label;
};

/// A point of an x-y plot ringed and labelled: a float that failed, the most
/// biased float, where a statistic takes its value. The axes widen to show it.
struct Highlight {
    double x = 0.0, y = 0.0;
    std::string label;
};

/// A cell of one heatmap of a plot ringed and labelled, e.g. the cell with the
/// largest residual. Row 0 is at y_min, as in Heatmap::values.
struct CellHighlight {
    std::size_t heatmap = 0;
    int row = 0, col = 0;
    std::string label;
};

/// A value marked on the colour bar of a heatmap's scale (both signs on a
/// diverging one), e.g. the residual at which one cell alone fails. The scale
/// widens to show it.
struct ScaleMark {
    std::size_t heatmap = 0;
    double value = 0.0;
    std::string label;
};

struct SvgOptions {
    /// Prefix for the ids of gradients and patterns: unique per plot within
    /// one document, e.g. "p12-0".
    std::string id_prefix = "p";
    /// Size of a line, bar or point plot in CSS pixels (heatmaps size themselves).
    double width = 560.0;
    double height = 300.0;
    /// What the report adds to the plot a check made: the limits its judged
    /// quantity is compared with, and the points and cells worth a look.
    std::vector<LimitLine> limits;
    std::vector<Highlight> highlights;
    std::vector<CellHighlight> cells;
    std::vector<ScaleMark> scale_marks;
};

/// An <svg> element (with the SVG namespace, so that it is also well-formed
/// XML) drawing `plot`. The plot's title is left to the caller's caption.
/// Malformed data (mismatched lengths, NaN, non-positive values on a log axis)
/// is skipped or marked, never a crash.
std::string render_svg(const Plot& plot, const SvgOptions& options = {});

}  // namespace warpcheck
