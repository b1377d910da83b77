// validate/trust/fpr.h: the false-positive-rate tool over a program's own cases.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "validate/api/external.h"
#include "validate/trust/fpr.h"

namespace warpcheck {
namespace {

using ::testing::HasSubstr;

// A u64 -> [0,1) sampler of the top 16 bits whose neighbouring grid values are
// swapped: it claims to be monotone and steps down, so the exhaustive check
// (which does not depend on the seed) fails it the same way on every seed.
void register_swapped_sampler(Registry& registry) {
    registry.add_case(make_u64_float_case(
        {.family = "swapped_grid", .domain = chi2::Domain::interval(0, 1)}, {.shift = 48}, Monotone::Claimed,
        warp_of([](uint64_t u) { return static_cast<float>((u >> 48) ^ 1u) * 0x1p-16f; })
            .with_pdf([](float x) { return x >= 0 && x < 1 ? 1.0f : 0.0f; })));
}

// The same sampler without the swap: monotone, as claimed.
void register_grid_sampler(Registry& registry) {
    registry.add_case(make_u64_float_case(
        {.family = "grid", .domain = chi2::Domain::interval(0, 1)}, {.shift = 48}, Monotone::Claimed,
        warp_of([](uint64_t u) { return static_cast<float>(u >> 48) * 0x1p-16f; })
            .with_pdf([](float x) { return x >= 0 && x < 1 ? 1.0f : 0.0f; })));
}

// A sampler that ends its process: only an isolated run survives it.
void register_exiting_sampler(Registry& registry) {
    registry.add_case(make_warp_case({.family = "exits", .domain = chi2::Domain::interval(0, 1)},
                                     warp_of([](float) -> float { std::_Exit(7); })
                                         .with_pdf([](float) { return 1.0f; })));
}

std::string run_fpr(void (*register_cases)(Registry&), int& status, const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args{"test_fpr", "--runs",  "3",           "--samples", "1000",
                                  "--check",  "exhaustive", "--check", "consistency"};
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    ::testing::internal::CaptureStdout();
    status = fpr_main(static_cast<int>(argv.size()), argv.data(), {.name = "test_fpr", .register_cases = register_cases});
    return ::testing::internal::GetCapturedStdout();
}

TEST(FalsePositiveRate, SeedIndependentFailureCountsInEveryRun) {
    int status = -1;
    const std::string out = run_fpr(register_swapped_sampler, status);
    // The sweep runs once, with the first seed; its failure fails all three runs.
    EXPECT_THAT(out, HasSubstr("runs with a failure: 3 = 1.0000"));
    EXPECT_THAT(out, HasSubstr("exhaustive swapped_grid"));
    EXPECT_EQ(status, 1) << out;  // 0.2 lies outside [0.29, 1]
}

TEST(FalsePositiveRate, ProgramsOwnCasesPassingEveryRun) {
    int status = -1;
    const std::string out = run_fpr(register_grid_sampler, status);
    EXPECT_THAT(out, HasSubstr("3 runs of 2 checks"));
    EXPECT_THAT(out, HasSubstr("runs with a failure: 0 = 0.0000"));
    EXPECT_EQ(status, 0) << out;  // 0.2 lies inside [0, 0.71]
}

TEST(FalsePositiveRate, IsolatedByDefault) {
    // issue 22: the measurement runs isolated, so a job that ends its process
    // (or overruns its CPU budget) is that run's ERROR, and the count goes on.
    int status = -1;
    const std::string out = run_fpr(register_exiting_sampler, status);
    EXPECT_THAT(out, HasSubstr("isolated)"));
    EXPECT_THAT(out, HasSubstr("runs with a failure: 3 = 1.0000"));
    EXPECT_THAT(out, HasSubstr("consistency exits"));
    EXPECT_EQ(status, 1) << out;
}

TEST(FalsePositiveRateDeathTest, NotIsolatedOnlyOnRequest) {
    int status = -1;
    EXPECT_EXIT(run_fpr(register_exiting_sampler, status, {"--no-isolation"}), ::testing::ExitedWithCode(7), "");
}

}  // namespace
}  // namespace warpcheck
