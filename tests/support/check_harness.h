// Runs one check on one warp case outside the CLI, the way the runner does.
#pragma once

#include <string>

#include "validate/check.h"
#include "validate/runner.h"

namespace warpcheck::testing {

inline CheckResult run_check(const Check& check, const WarpCase& warp, uint64_t samples = 200'000,
                             unsigned threads = 2, uint64_t seed = 1) {
    RunOptions options;
    options.samples = samples;
    options.threads = threads;
    options.seed = seed;
    Job job{&warp, &check};
    RunResult run = run_jobs({job}, options);
    return run.results.at(0);
}

}  // namespace warpcheck::testing
