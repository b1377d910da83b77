// Samples from elsewhere as rows: record and replay give the figures of the warp
// itself; ulps between two builds; two-sample tests of independent draws;
// independent draws against a pdf. Built-in cases are the warps, seeded.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sampling/hemisphere.h"
#include "sampling/pcg32.h"
#include "support/builtin_case.h"
#include "validate/api/registry.h"
#include "validate/run/runner.h"
#include "validate/samples/replay_run.h"
#include "validate/samples/sample_set.h"
#include "validate/samples/two_sample_comparison.h"
#include "validate/samples/ulp_comparison.h"

namespace warpcheck {
namespace {

const Registry& checks() {
    static const Registry registry = [] {
        Registry r;
        register_builtin_checks(r);
        return r;
    }();
    return registry;
}

std::vector<Job> jobs_of(const WarpCase& warp, std::vector<std::string> names) {
    std::vector<Job> jobs;
    for (const std::string& name : names) jobs.push_back({&warp, checks().find_check(name)});
    return jobs;
}

TEST(UlpDistance, CountsFloatsBetween) {
    EXPECT_EQ(ulp_distance(0.0f, -0.0f), 0u);
    EXPECT_EQ(ulp_distance(1.0f, std::nextafter(1.0f, 2.0f)), 1u);
    EXPECT_EQ(ulp_distance(-0x1p-149f, 0x1p-149f), 2u);
    EXPECT_EQ(ulp_distance(1.0f, std::nanf("")), std::numeric_limits<uint64_t>::max());
    // Below the floor, in ulps of the floor: 1e-9 against 0 is under one ulp of 1.
    EXPECT_GT(ulp_distance(1e-9f, 0.0f), 100'000'000u);
    EXPECT_EQ(ulp_distance(1e-9f, 0.0f, 1.0f), 1u);
    EXPECT_EQ(ulp_distance(std::nanf(""), 0.0f, 1.0f), std::numeric_limits<uint64_t>::max());
}

TEST(CompareSameInputs, StatesTheHistogramAndFailsBeyondTheClaimOrOnNaN) {
    std::vector<WarpOutput> a, b;
    for (int i = 0; i < 100; ++i) {
        const float v = 0.01f * static_cast<float>(i + 1);
        a.push_back({v, v, v});
        b.push_back({i % 10 == 0 ? std::nextafter(v, 1.0f) : v, v, v});
    }
    UlpComparison how;
    CheckResult exact = compare_same_inputs(a, b, how);
    EXPECT_EQ(exact.verdict, Verdict::Fail);
    EXPECT_EQ(exact.figure("over_tolerance"), 10.0);
    EXPECT_EQ(exact.figure("identical_fraction"), 0.9);
    ASSERT_EQ(exact.tables.size(), 2u);
    EXPECT_EQ(exact.tables[0].rows, (std::vector<std::vector<std::string>>{{"0", "90"}, {"1", "10"}}));
    EXPECT_EQ(exact.tables[1].rows.size(), 10u) << "the worst inputs";
    how.max_ulps = 1;
    EXPECT_EQ(compare_same_inputs(a, b, how).verdict, Verdict::Pass);
    b[3][2] = std::nanf("");
    const CheckResult with_nan = compare_same_inputs(a, b, how);
    EXPECT_EQ(with_nan.verdict, Verdict::Fail);
    EXPECT_NE(with_nan.message.find("NaN, which never agrees"), std::string::npos);
}

TEST(RecordAndReplay, TheSameOutputsGiveTheSameFiguresAndOthersAreJudged) {
    const WarpCase& warp = testing::builtin_case("cosine_hemisphere");
    RunOptions options;
    options.samples = 20'000;
    options.threads = 2;
    const std::vector<Job> jobs = jobs_of(warp, {"consistency", "chi2", "unbinned"});
    const Recording rec = record_run(warp, jobs, options);
    ASSERT_EQ(rec.run.results.size(), 3u);
    EXPECT_GT(rec.samples.inputs.size(), 2 * options.samples);
    const RunResult replayed = replay_run(warp, rec.samples, jobs, options);
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(replayed.results[i].verdict, rec.run.results[i].verdict);
        ASSERT_EQ(replayed.results[i].figures.size(), rec.run.results[i].figures.size());
        for (std::size_t k = 0; k < replayed.results[i].figures.size(); ++k) {
            const double x = replayed.results[i].figures[k].value, y = rec.run.results[i].figures[k].value;
            EXPECT_TRUE(x == y || (std::isnan(x) && std::isnan(y))) << replayed.results[i].figures[k].name;
        }
    }
    // A device whose directions are 1% short of unit length: outside the hemisphere.
    RecordedSamples bent = rec.samples;
    for (WarpOutput& o : bent.outputs) o = {o[0] * 0.99f, o[1] * 0.99f, o[2] * 0.99f};
    const RunResult wrong = replay_run(warp, bent, jobs, options);
    EXPECT_EQ(wrong.results[0].verdict, Verdict::Fail);
    // Another seed asks for inputs nobody recorded: an error that says so.
    options.seed = 2;
    const RunResult other = replay_run(warp, rec.samples, jobs_of(warp, {"chi2"}), options);
    EXPECT_EQ(other.results[0].verdict, Verdict::Error);
    EXPECT_NE(other.results[0].message.find("was not recorded"), std::string::npos) << other.results[0].message;
}

TEST(RecordAndReplay, ATableThatContradictsItselfIsRefused) {
    const WarpCase& warp = testing::builtin_case("cosine_hemisphere");
    RecordedSamples table;
    table.inputs = {{{0.5f, 0.5f, 0.0f}, 0}, {{0.5f, 0.5f, 0.0f}, 0}};
    table.outputs = {{0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.5f}};
    EXPECT_THROW(ReplayCase(warp, table), std::invalid_argument);
    table.outputs.pop_back();
    EXPECT_THROW(ReplayCase(warp, table), std::invalid_argument);
}

/// n cosine-hemisphere directions from the device's own generator, u.x scaled by `scale`.
std::vector<WarpOutput> draws(uint64_t seed, std::size_t n, float scale = 1.0f) {
    Pcg32 rng(seed, 99);
    std::vector<WarpOutput> out;
    for (std::size_t i = 0; i < n; ++i) {
        const float ux = rng.next_float() * scale, uy = rng.next_float();
        const Vector3f w = CosineHemisphere{}.sample({ux, uy});
        out.push_back({w.x, w.y, w.z});
    }
    return out;
}

TEST(CompareIndependent, PassesACorrectPairFailsAOnePercentErrorAndStatesItsPower) {
    RunOptions options;
    TwoSampleComparison how;
    how.domain = chi2::Domain::hemisphere();
    const auto a = draws(1, 200'000), b = draws(2, 200'000), c = draws(3, 200'000, 0.99f);
    RunResult good = run_of_rows({compare_independent(a, b, how, options)}, options, "test");
    EXPECT_EQ(good.results[0].verdict, Verdict::Pass) << good.results[0].summary;
    EXPECT_LT(good.results[0].figure("power_tilt_ad").value_or(1.0), 0.05);
    RunResult bad = run_of_rows({compare_independent(a, c, how, options)}, options, "test");
    EXPECT_EQ(bad.results[0].verdict, Verdict::Fail) << bad.results[0].summary;
    auto with_nan = b;
    with_nan[7][0] = std::nanf("");
    EXPECT_EQ(compare_independent(a, with_nan, how, options).verdict, Verdict::Fail);
}

TEST(JudgeSampleSet, IndependentDrawsAgainstThePdf) {
    const WarpCase& warp = testing::builtin_case("cosine_hemisphere");
    RunOptions options;
    const RunResult good = run_of_rows(judge_sample_set(warp, draws(4, 100'000), options), options, "test");
    ASSERT_EQ(good.results.size(), 2u);
    EXPECT_TRUE(good.all_passed()) << good.results[1].summary;
    const RunResult bad = run_of_rows(judge_sample_set(warp, draws(4, 100'000, 0.97f), options), options, "test");
    EXPECT_EQ(bad.results[1].verdict, Verdict::Fail) << bad.results[1].summary;
}

}  // namespace
}  // namespace warpcheck
