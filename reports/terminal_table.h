// The pass/fail table that `validate` prints: one row per (case, check), then
// a summary per warp family, the passing results closest to their limits, the
// failures with the command that reruns each, and the totals.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>

#include "reports/result.h"

namespace warpcheck {

struct TableStyle {
    bool color = false;          ///< ANSI colours for verdicts (only on a terminal)
    bool failures_only = false;  ///< print only rows that did not pass
    bool timings = false;        ///< after the table, where the run's time went (print_timings)
    /// Columns the rows fit in: long case names (their families, never their
    /// parameters) and key figures are cut, the cut marked by "…" (the JSON
    /// and HTML reports keep them whole). 0: no limit.
    std::size_t width = 120;
    bool families = true;        ///< the summary per warp family
    std::size_t weakest = 3;     ///< passing rows listed per kind of limit as closest to it (0: none)
};

/// How far a row is from the limits that judge it: `p_over_level` for a
/// statistical row (its p-value over the per-test level: it fails below 1),
/// `of_tolerance` for a row with quantities held under limits (the largest
/// margin of its judged lines of that kind, JudgedQuantity::Margin::OfLimit:
/// it fails above 1), named by `tolerance_figure` (that line's quantity). Read
/// from the judged lines the check wrote (validate/checks/judged.h), never
/// from figure names; a limit of 0 (an exact rule) gives no fraction.
struct RowMargin {
    std::optional<double> p_over_level;
    std::optional<double> of_tolerance;
    std::string tolerance_figure;
};
RowMargin row_margin(const CheckResult& r);

/// The margin as the table shows it: "390x level" or "0.4 of tol"; empty if
/// the row has neither.
std::string margin_text(const RowMargin& m);

/// A case name cut to `columns`: the family is shortened in its middle, to a
/// lone "…" if need be, and the parameters, which tell a family's rows apart,
/// are kept whole: "trowbr…visible[ax=0.3,ay=0.05,theta_o=60]". Only when
/// "…" and the parameters do not fit is the name cut at its end.
std::string fit_case_name(const std::string& name, std::size_t columns);

/// Prints the table, then the summaries, the failures with their rerun
/// commands, and the totals.
void print_table(const RunResult& run, std::ostream& out, const TableStyle& style = {});

/// Per warp family (the case name before '['): cases and rows by verdict.
void print_family_summary(const RunResult& run, std::ostream& out, bool failures_only = false);

/// The passing rows closest to their limits: the `count` smallest p-values
/// against the level, and the `count` largest fractions of a tolerance.
void print_weakest(const RunResult& run, std::ostream& out, std::size_t count, std::size_t width = 120);

/// Where the time went: seconds per check name over all cases, then the
/// slowest rows with the parts of their compute (CheckResult::phases).
void print_timings(const RunResult& run, std::ostream& out, std::size_t slowest = 10);

/// The one-line summary: "42 checks: 41 passed, 1 failed, 0 errors in 3.2 s (seed 1, ...)".
void print_summary(const RunResult& run, std::ostream& out);

}  // namespace warpcheck
