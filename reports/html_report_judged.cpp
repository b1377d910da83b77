// A row's closeness to its limit, for the report's margin. The judged
// quantities themselves are the checks' own (CheckResult::judged,
// validate/checks/judged.h), and so are their legends (RunInfo::legends, from
// Check::legend): no check is named here.
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "reports/html_report_parts.h"
#include "reports/terminal_table.h"
#include "reports/text.h"

namespace warpcheck::html {

std::optional<double> closeness(const CheckResult& r) {
    const RowMargin m = row_margin(r);
    std::optional<double> c;
    if (m.p_over_level) c = *m.p_over_level > 0.0 ? 1.0 / *m.p_over_level : HUGE_VAL;
    if (m.of_tolerance && (!c || *m.of_tolerance > *c || std::isnan(*m.of_tolerance))) c = *m.of_tolerance;
    if (c && std::isnan(*c)) c = HUGE_VAL;  // NaN is the worst
    return c;
}

}  // namespace warpcheck::html
