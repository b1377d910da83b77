// The parts of the HTML report (reports/html_report.cpp), each in its own file:
//  - html_report_assets.cpp: the style sheet and the script;
//  - html_report_judged.cpp: the legend of each check's p-value, a row's
//    closeness to its limit, an unbinned row's judged tests;
//  - html_report_row.cpp: the order of the rows (failures, then the weakest)
//    and the details of one row.
// Internal to reports/: nothing here is installed as an interface.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "reports/result.h"
#include "reports/result_tables.h"
#include "reports/svg_plot.h"

namespace warpcheck::html {

/// The page's style sheet and its script (search, filters, unpacking).
std::string_view style_sheet();
std::string_view script();

/// The share of a chi-square check's level that its largest cell residual
/// gets (chi2/local_residual.h, kLocalLevelShare), for the cell level the
/// residual heatmap marks.
inline constexpr double kChi2LocalShare = 0.2;

/// The cell a chi-square row's evidence rings as its largest residual, and
/// that residual: the check's (figures local_cell and local_max_residual: the
/// cell of the smallest per-cell p-value). Where that p-value underflowed to 0
/// (local_p_value 0), every cell at 0 ties and the check's is only the first
/// of them: the ring then goes to the cell of the largest |residual| of the
/// row's plotted residuals, the departure the table of cells lists first.
struct RingedCell {
    std::size_t index = 0;  ///< the cell: a residual heatmap's value index, or the residual series' point
    double residual = 0.0;
};
std::optional<RingedCell> ringed_cell(const CheckResult& r);

/// What the report draws into plot `index` of `r`: the limit its judged
/// quantity is compared with, the points that failed or decide the statistic.
void annotate_plot(const CheckResult& r, std::size_t index, SvgOptions& options);

/// A sentence under plot `index` of `r` saying what is judged in it and what
/// the drawn limits mean; empty if there is nothing to say.
std::string plot_note(const CheckResult& r, std::size_t index);

/// How close a row came to its limit, as the terminal's margin column reads it
/// (reports/terminal_table.h: row_margin): level / p for a statistical row,
/// error / tolerance otherwise, the larger when a row has both; 1 at the
/// limit. Empty when the row has neither.
std::optional<double> closeness(const CheckResult& r);

/// The rows in the order the report shows them: grouped by family (the case
/// name before '['), families with failures first, then errors, then by their
/// weakest row; within a family failures, errors, passes from the closest to
/// its limit, then n/a. Ties keep registry order.
struct FamilyGroup {
    std::string family;
    std::vector<std::size_t> rows;  ///< indices into RunResult::results
};
std::vector<FamilyGroup> family_groups(const RunResult& run);

/// The details of row `index`: message, facts, rerun command, the judged
/// quantities, plots with their limits, tables, and every figure behind a toggle.
std::string row_body(const RunResult& run, std::size_t index);

}  // namespace warpcheck::html
