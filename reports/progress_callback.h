// How a run reports its progress. The runner (validate/) calls it and the
// progress line (reports/progress.h) is one implementation, so the type lives
// in the results library that both depend on.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace warpcheck {

/// Called after each finished step: `done` of `total` steps are finished, `what`
/// names the step that just finished (e.g. "chi2 uniform_disk[]").
using ProgressCallback = std::function<void(std::size_t done, std::size_t total, const std::string& what)>;

}  // namespace warpcheck
