// The validate command: exit statuses and messages for good and bad input.
#include <gtest/gtest.h>

#include "support/run_command.h"

namespace warpcheck {
namespace {

using testing::run_validate;

TEST(Cli, FilteredRunPassesAndPrintsTheTable) {
    const auto r = run_validate("--filter uniform_cone --samples 20000 --check roundtrip --check consistency");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("uniform_cone[cos_theta_max=0.3]"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("roundtrip"), std::string::npos);
    EXPECT_NE(r.output.find("0 failed, 0 errors"), std::string::npos) << r.output;
}

TEST(Cli, ExactCaseNameSelectsOneCase) {
    const auto r = run_validate("--filter 'uniform_cone[cos_theta_max=0.3]' --check roundtrip --samples 10000");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find("cos_theta_max=0.99"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("1 checks: 1 passed"), std::string::npos) << r.output;
}

// Cases that demonstrate a known flaw stay out of --all, run when asked for,
// and then fail with their numbers.
TEST(Cli, KnownFlawsRunOnlyWhenAskedFor) {
    const auto plain = run_validate("--filter unit_float_mul --check exhaustive");
    EXPECT_EQ(plain.status, 0) << plain.output;
    EXPECT_EQ(plain.output.find("unit_float_mul32 "), std::string::npos) << plain.output;
    const auto named = run_validate("--filter unit_float_mul32 --check exhaustive");
    EXPECT_EQ(named.status, 1) << named.output;
    EXPECT_NE(named.output.find("83886081 distinct, 128 inputs -> 1"), std::string::npos) << named.output;
    const auto flawed = run_validate("--filter lerp_offset --include-flawed --check exhaustive");
    EXPECT_EQ(flawed.status, 1) << flawed.output;
    EXPECT_NE(flawed.output.find("64 inputs -> 101"), std::string::npos) << flawed.output;
}

TEST(Cli, ListShowsCasesAndChecks) {
    const auto r = run_validate("--list");
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.output.find("cosine_hemisphere"), std::string::npos);
    EXPECT_NE(r.output.find("roundtrip"), std::string::npos);
}

TEST(Cli, BadInputExitsTwoWithAMessage) {
    struct Case {
        const char* args;
        const char* message;
    };
    const Case cases[] = {
        {"--all --bogus", "bogus"},
        {"--filter no_such_warp", "no warp case matches 'no_such_warp'"},
        {"--all --check no_such_check", "unknown check 'no_such_check'"},
        {"", "nothing selected"},
        {"--all --samples 0", "samples"},
        {"--all --samples abc", "samples"},
        {"--all --alpha 2", "alpha"},
        {"--all --alpha nan", "'nan' is not a finite number"},
        {"--all --time-budget nan", "'nan' is not a finite number"},
        {"--all --seed 18446744073709551616", "is not a seed: an integer from 0 to 18446744073709551615"},
        {"--all --seed 12x", "is not a seed"},
        {"--all --threads -3", "threads"},
        {"--all --report /nonexistent/dir/r.html", "cannot write '/nonexistent/dir/r.html'"},
        {"--all --json /", "cannot write '/'"},
        {"--all --filter cone", "exclude each other"},
    };
    for (const Case& c : cases) {
        const auto r = run_validate(c.args);
        EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
    }
}

TEST(Cli, HelpAndVersionExitZero) {
    EXPECT_EQ(run_validate("--help").status, 0);
    const auto v = run_validate("--version");
    EXPECT_EQ(v.status, 0);
    EXPECT_NE(v.output.find("warpcheck"), std::string::npos);
}

}  // namespace
}  // namespace warpcheck
