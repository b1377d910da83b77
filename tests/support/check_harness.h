// Runs one check on one warp case outside the CLI, the way the runner does.
#pragma once

#include <string>

#include "validate/check.h"
#include "validate/runner.h"

namespace warpcheck::testing {

/// Time budget of checks run by tests: generous, so that only the test of the
/// budget itself ever abandons a check.
inline constexpr double kTestTimeBudget = 3600.0;

inline CheckResult run_check(const Check& check, const WarpCase& warp, uint64_t samples = 200'000,
                             unsigned threads = 2, uint64_t seed = 1) {
    RunOptions options;
    options.samples = samples;
    options.threads = threads;
    options.seed = seed;
    // Sanitizer builds run several times slower; a check abandoned for its budget
    // would leave a thread using the test's warp after the test ends.
    options.check_time_budget = kTestTimeBudget;
    Job job{&warp, &check};
    RunResult run = run_jobs({job}, options);
    return run.results.at(0);
}

}  // namespace warpcheck::testing
