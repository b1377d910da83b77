// Runs one check on one warp case outside the CLI, the way the runner does.
#pragma once

#include <gtest/gtest.h>

#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "validate/checks/check.h"
#include "validate/run/runner.h"

namespace warpcheck::testing {

/// Time budget of checks run by tests in-process. In-process runs never abandon
/// a check (they only ask it to stop), so this only has to exceed what a check
/// takes in the slowest (sanitizer) build; tests of the budget itself run
/// isolated with budgets of a second or two.
inline constexpr double kTestTimeBudget = 600.0;

/// A figure of a result; a test failure (and NaN) where the check wrote none.
inline double figure_of(const CheckResult& r, std::string_view name) {
    const std::optional<double> v = r.figure(name);
    if (!v) ADD_FAILURE() << "no figure " << name << " in " << r.check_name;
    return v.value_or(std::numeric_limits<double>::quiet_NaN());
}

inline CheckResult run_check(const Check& check, const WarpCase& warp, uint64_t samples = 200'000,
                             unsigned threads = 2, uint64_t seed = 1) {
    RunOptions options;
    options.samples = samples;
    options.threads = threads;
    options.seed = seed;
    // In-process (the library's default): a debugger or sanitizer sees the warp
    // in the test's own process.
    options.check_time_budget = kTestTimeBudget;
    Job job{&warp, &check};
    RunResult run = run_jobs({job}, options);
    return run.results.at(0);
}

}  // namespace warpcheck::testing
