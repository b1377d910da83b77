// The pass/fail table that `validate` prints: one row per (case, check).
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "reports/result.h"

namespace warpcheck {

struct TableStyle {
    bool color = false;         ///< ANSI colours for verdicts (only on a terminal)
    bool failures_only = false; ///< print only rows that did not pass
    bool timings = false;       ///< after the table, where the run's time went (print_timings)
};

/// `text` safe to print on a terminal: every byte that a terminal could take as
/// a control (C0 controls and DEL, UTF-8-encoded C1 controls, bytes that are not
/// valid UTF-8) becomes a visible \xNN escape, so that a case name or a message
/// can neither move the cursor nor fake a row ('\n' and '\t' included). Other
/// text, UTF-8 included, is unchanged.
std::string terminal_text(std::string_view text);

/// Prints the table, then the summary line and the rerun command of each
/// failure; names, key figures and messages pass through terminal_text.
void print_table(const RunResult& run, std::ostream& out, const TableStyle& style = {});

/// Where the time went: seconds per check name over all cases, then the
/// slowest rows with the parts of their compute (CheckResult::phases).
void print_timings(const RunResult& run, std::ostream& out, std::size_t slowest = 10);

/// The one-line summary: "42 checks: 41 passed, 1 failed, 0 errors in 3.2 s (seed 1, ...)".
void print_summary(const RunResult& run, std::ostream& out);

}  // namespace warpcheck
