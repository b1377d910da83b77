// The level at which a check states its power. The runner's per-test level
// depends on how many tests the whole run holds, which a check does not know
// while it runs; power is stated at the level of a typical full run instead
// (validate --all: 136 tests with a p-value at the time of writing), corrected for the tests that the
// check combines. Power depends on the level only through its logarithm: at
// 10 times the level the stated deviations shrink by ~5%.
#pragma once

#include "chi2/multiple_testing.h"
#include "validate/checks/check.h"

namespace warpcheck {

inline constexpr int kPlannedTestsPerRun = 140;

/// The level of one of `tests_in_check` tests combined by chi2::sidak_min_p.
inline double power_level(const RunOptions& options, int tests_in_check) {
    return chi2::sidak_level(chi2::sidak_level(options.alpha, kPlannedTestsPerRun), tests_in_check);
}

}  // namespace warpcheck
