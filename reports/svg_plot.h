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

struct SvgOptions {
    /// Prefix for the ids of gradients and patterns: unique per plot within
    /// one document, e.g. "p12-0".
    std::string id_prefix = "p";
    /// Size of a line, bar or point plot in CSS pixels (heatmaps size themselves).
    double width = 560.0;
    double height = 300.0;
    /// Marks drawn besides the plot's own (Plot::limits, highlights, cells,
    /// scale_marks), which render_svg draws first.
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
