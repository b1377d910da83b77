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
