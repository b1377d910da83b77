// Isolated jobs: a warp that crashes, aborts, exits or allocates without bound
// is one ERROR row naming the cause; results travel from the worker complete
// and bit for bit.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <limits>
#include <new>
#include <vector>

#include "sampling/hemisphere.h"
#include "validate/checks/checks.h"
#include "validate/result_codec.h"
#include "validate/runner.h"

#if defined(__SANITIZE_ADDRESS__)
#define WARPCHECK_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define WARPCHECK_TEST_ASAN 1
#endif
#endif

namespace warpcheck {
namespace {

TEST(ResultCodec, EveryFieldRoundTripsBitForBit) {
    CheckResult r;
    r.case_name = "c[a=1]";
    r.check_name = "chi2";
    r.verdict = Verdict::Fail;
    r.summary = "s";
    r.message = std::string("bytes \xff\x00 kept", 13);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    r.figures = {{"nan", nan}, {"inf", -std::numeric_limits<double>::infinity()}, {"zero", -0.0}, {"x", 0.1}};
    r.p_value = nan;
    r.level = 1e-300;
    Plot plot;
    plot.kind = Plot::Kind::Heatmaps;
    plot.title = "t";
    plot.log_y = true;
    plot.series = {{"s", {1, 2}, {nan, 4}}};
    Heatmap h;
    h.label = "h";
    h.rows = 1;
    h.cols = 2;
    h.values = {nan, 5e-324};
    h.y_max = 3;
    h.color_scale = Heatmap::ColorScale::Diverging;
    h.min_color_limit = 4;
    plot.heatmaps = {h};
    r.plots = {plot};
    r.tables = {{"worst", {"u", "x"}, {{"1", "2"}, {"3", "4"}}}};
    r.stream_seed = ~uint64_t{0};
    r.stream_sequence = 7;
    r.samples = 123;
    r.seconds = 0.25;
    r.phases = {{"integration", 0.125}, {"sampling+binning", 0x1.123456789abcdp-7}};
    r.rerun_command = "validate --filter 'c[a=1]'";

    const auto back = decode_result(encode_result(r));
    ASSERT_TRUE(back.has_value());
    // Re-encoding gives the same bytes: every field, every bit of every double.
    EXPECT_EQ(encode_result(*back), encode_result(r));
    EXPECT_EQ(back->message, r.message);
    EXPECT_EQ(std::memcmp(&back->figures[2].value, &r.figures[2].value, sizeof(double)), 0);
    EXPECT_TRUE(std::isnan(*back->p_value));
    EXPECT_EQ(back->plots.at(0).heatmaps.at(0).values.at(1), 5e-324);
    EXPECT_EQ(back->tables.at(0).rows.at(1).at(1), "4");
    ASSERT_EQ(back->phases.size(), 2u);
    EXPECT_EQ(back->phases[1].phase, "sampling+binning");
    EXPECT_EQ(back->phases[1].seconds, 0x1.123456789abcdp-7);
    // Half an encoding (a worker that died while writing) is no result.
    const std::string bytes = encode_result(r);
    EXPECT_FALSE(decode_result(bytes.substr(0, bytes.size() / 2)).has_value());
}

// A warp whose sample() does `misbehave` on the first call and is fine after.
std::unique_ptr<WarpCase> hostile(const char* name, void (*misbehave)()) {
    return make_warp_case({name, {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                          [misbehave](Point2f u) {
                              misbehave();
                              return UniformHemisphere{}.sample(u);
                          },
                          [](Vector3f x) { return UniformHemisphere{}.pdf(x); },
                          [](Vector3f x) { return UniformHemisphere{}.invert(x); });
}

RunResult run_isolated(const std::vector<std::unique_ptr<WarpCase>>& cases, double budget = 20) {
    const auto check = make_roundtrip_check();
    std::vector<Job> jobs;
    for (const auto& c : cases) jobs.push_back({c.get(), check.get()});
    RunOptions options;
    options.samples = 20'000;
    options.threads = 2;
    options.check_time_budget = budget;
    Isolation isolation;
    isolation.enabled = true;
    isolation.memory_limit = uint64_t{1} << 30;
    return run_jobs(jobs, options, {}, isolation);
}

// A rejection loop that never accepts must not hang the run: its worker is
// killed when its CPU time budget runs out, and the other checks finish.
TEST(Isolation, SamplerThatNeverTerminatesIsAnErrorAfterItsBudget) {
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(hostile("never_accepts", [] {
        volatile float candidate = 0.5f;
        while (candidate < 2.0f) candidate = candidate * 0.5f;  // rejection that never accepts
    }));
    cases.push_back(make_warp_case({"fine", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                                   UniformHemisphere{}));
    const RunResult run = run_isolated(cases, 1.0);
    ASSERT_EQ(run.results.size(), 2u);
    EXPECT_EQ(run.results[0].verdict, Verdict::Error);
    EXPECT_EQ(run.results[0].summary, "error: over time budget");
    EXPECT_NE(run.results[0].message.find("over its CPU time budget of 1 s"), std::string::npos)
        << run.results[0].message;
    EXPECT_EQ(run.results[1].verdict, Verdict::Pass) << run.results[1].message;
    EXPECT_EQ(run.info.abandoned_checks, 1);
}

TEST(Isolation, ExitAndRunawayAllocationAreErrorRows) {
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(make_warp_case({"fine", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                                   UniformHemisphere{}));
    cases.push_back(hostile("exits0", [] { std::exit(0); }));
    cases.push_back(hostile("exits3", [] { std::exit(3); }));
#ifndef WARPCHECK_TEST_ASAN
    cases.push_back(hostile("allocates", [] {
        static std::vector<std::vector<char>> hoard;
        for (;;) hoard.emplace_back(std::size_t{64} << 20);
    }));
#endif
    const RunResult run = run_isolated(cases);
    ASSERT_EQ(run.results.size(), cases.size());
    EXPECT_EQ(run.results[0].verdict, Verdict::Pass) << run.results[0].message;
    for (std::size_t i = 1; i < cases.size(); ++i) EXPECT_EQ(run.results[i].verdict, Verdict::Error);
#ifndef WARPCHECK_TEST_ASAN
    EXPECT_EQ(run.results[1].message, "called exit(0) before returning a result");
    EXPECT_EQ(run.results[2].message, "exited with status 3 before returning a result");
#else  // LeakSanitizer checks at exit() and may change the status
    EXPECT_NE(run.results[1].message.find("before returning a result"), std::string::npos);
    EXPECT_NE(run.results[2].message.find("before returning a result"), std::string::npos);
#endif
    EXPECT_EQ(run.results[1].case_name, "exits0");
#ifndef WARPCHECK_TEST_ASAN
    EXPECT_NE(run.results[3].message.find("ran out of memory"), std::string::npos) << run.results[3].message;
#endif
}

#ifndef WARPCHECK_TEST_ASAN  // AddressSanitizer catches SIGSEGV itself and exits instead
TEST(Isolation, CrashesAreErrorRowsNamingTheSignal) {
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(hostile("segfaults", [] { std::raise(SIGSEGV); }));
    cases.push_back(hostile("aborts", [] { std::abort(); }));
    cases.push_back(make_warp_case({"fine", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                                   UniformHemisphere{}));
    const RunResult run = run_isolated(cases);
    ASSERT_EQ(run.results.size(), 3u);
    EXPECT_EQ(run.results[0].message, "killed by signal 11 (SIGSEGV)");
    EXPECT_EQ(run.results[1].message, "aborted (SIGABRT)");
    EXPECT_EQ(run.results[2].verdict, Verdict::Pass) << run.results[2].message;
}
#endif

}  // namespace
}  // namespace warpcheck
