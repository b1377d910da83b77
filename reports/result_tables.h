// Reading a result's tables by their column names: what the unbinned checks'
// table of tests says was judged, read by the check's own judgement
// (validate/checks/unbinned/unbinned_check.cpp) and by the report's plot marks.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "reports/result.h"

namespace warpcheck {

/// The judged test of each marginal of an unbinned row, from its table of
/// tests (columns "marginal", "test", "judged" = "yes"): (marginal label,
/// short test name: "ad", "kuiper", "ks").
inline std::vector<std::pair<std::string, std::string>> judged_unbinned_tests(const CheckResult& r) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const Table& t : r.tables) {
        const auto at = [&](std::string_view c) { return std::find(t.columns.begin(), t.columns.end(), c) - t.columns.begin(); };
        const auto m = at("marginal"), test = at("test"), judged = at("judged");
        const auto n = static_cast<std::ptrdiff_t>(t.columns.size());
        if (m == n || test == n || judged == n) continue;
        for (const auto& row : t.rows)
            if (static_cast<std::ptrdiff_t>(row.size()) == n && row[static_cast<std::size_t>(judged)] == "yes")
                out.emplace_back(row[static_cast<std::size_t>(m)], row[static_cast<std::size_t>(test)]);
    }
    return out;
}

}  // namespace warpcheck
