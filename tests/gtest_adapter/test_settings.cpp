// The GoogleTest adapter's settings from the environment: the time budget
// and memory limit as `validate` reads them (--time-budget, --memory-limit),
// beside the seed, sample count and alpha; an invalid one names its variable.
#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

#include "validate/api/external.h"
#include "validate/gtest/job_tests.h"
#include "validate/gtest/warpcheck_gtest.h"
#include "tests/gtest_adapter/scoped_env.h"

namespace warpcheck {
namespace {

using gtest_adapter_tests::ScopedEnv;

/// The identity on [0,1) that never returns from its first sample.
struct Spins {
    float sample(float u) const {
        volatile bool spinning = true;
        while (spinning) {
        }
        return u;
    }
    float pdf(float x) const { return x >= 0 && x <= 1 ? 1.0f : 0.0f; }
};

TEST(GtestSettings, TimeBudgetAndMemoryLimitComeFromTheEnvironment) {
    const ScopedEnv budget("WARPCHECK_TIME_BUDGET", "2.5");
    const ScopedEnv memory("WARPCHECK_MEMORY_LIMIT", "2048");
    const gtest::Settings s = gtest::settings_from_environment();
    EXPECT_TRUE(s.run.time_budget_set);
    EXPECT_EQ(s.run.check_time_budget, 2.5);
    ASSERT_TRUE(s.memory_limit_mib);
    EXPECT_EQ(*s.memory_limit_mib, 2048u);
}

TEST(GtestSettings, AnInvalidBudgetOrLimitNamesItsVariable) {
    {
        const ScopedEnv budget("WARPCHECK_TIME_BUDGET", "forever");
        try {
            (void)gtest::settings_from_environment();
            FAIL() << "an invalid time budget was taken";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("WARPCHECK_TIME_BUDGET='forever' is not a finite number"),
                      std::string::npos)
                << e.what();
        }
    }
    const ScopedEnv memory("WARPCHECK_MEMORY_LIMIT", "-1");
    EXPECT_THROW((void)gtest::settings_from_environment(), std::invalid_argument);
}

// A warp that never returns is an error within the budget the environment
// gives (1 s of CPU time), not a wait of the default 60 s per check.
TEST(GtestSettings, AWarpOverTheTimeBudgetFailsWithinIt) {
    const ScopedEnv budget("WARPCHECK_TIME_BUDGET", "1");
    const ScopedEnv samples("WARPCHECK_SAMPLES", "1000");
    const auto warp = make_warp_case({.family = "spins",
                                      .description = "never returns from sample",
                                      .domain = chi2::Domain::interval(0, 1)},
                                     Spins{});
    const ::testing::AssertionResult result = gtest::WarpCasePasses("warp", warp);
    ASSERT_FALSE(result);
    EXPECT_NE(std::string(result.message()).find("over its CPU time budget of 1 s"), std::string::npos)
        << result.message();
}

}  // namespace
}  // namespace warpcheck
