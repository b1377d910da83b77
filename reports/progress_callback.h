// How a run reports its progress. The runner (validate/) calls it and the
// progress display (reports/progress.h) is one implementation, so the type lives
// in the results library that both depend on.
#pragma once

#include <cstddef>
#include <functional>
#include <string_view>

#include "reports/result.h"

namespace warpcheck {

/// One finished (case, check) job of a run.
struct ProgressStep {
    std::size_t done = 0;   ///< jobs finished, this one included
    std::size_t total = 0;  ///< jobs the run executes (n/a rows are not executed)
    std::string_view check;
    std::string_view case_name;
    /// The row as the check returned it: its verdict is final except that a
    /// statistical row's p-value is judged afterwards, at the run's level.
    const CheckResult* result = nullptr;
};

/// Called after each finished job, one call at a time, possibly from a job thread.
using ProgressCallback = std::function<void(const ProgressStep& step)>;

}  // namespace warpcheck
