// Verdict rules on code nobody here wrote: each wrong variant that an earlier
// rule let through fails the check meant to catch it, its correct twin passes
// every default check, and correct warps that merely look different pass.
#include <algorithm>
#include <string>

#include <gtest/gtest.h>

#include "support/check_harness.h"
#include "support/verdict_twins.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/input_chunks.h"
#include "validate/api/registry.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

using testing::VerdictTwin;

/// Every default check that applies, as `validate` runs them (Sidak over the case).
RunResult run_default_suite(std::unique_ptr<WarpCase> warp) {
    Registry registry;
    register_builtin_checks(registry);
    registry.add_case(std::move(warp));
    RunOptions options;
    options.threads = 2;
    options.check_time_budget = testing::kTestTimeBudget;
    return run_jobs(select_jobs(registry, {}, {}, options), options);
}

class VerdictTwinTest : public ::testing::TestWithParam<VerdictTwin> {};

TEST_P(VerdictTwinTest, WrongFailsItsCheckAndTwinPassesEverything) {
    const VerdictTwin& twin = GetParam();
    const RunResult wrong = run_default_suite(twin.wrong(twin.name));
    const auto it = std::find_if(wrong.results.begin(), wrong.results.end(),
                                 [&](const CheckResult& r) { return r.check_name == twin.caught_by; });
    ASSERT_NE(it, wrong.results.end()) << twin.caught_by << " did not run";
    EXPECT_EQ(it->verdict, Verdict::Fail) << twin.name << " (" << twin.bug << "): " << it->summary;

    const RunResult correct = run_default_suite(twin.correct(twin.name + "_twin"));
    for (const auto& r : correct.results) EXPECT_EQ(r.verdict, Verdict::Pass) << r.check_name << ": " << r.message;
}

INSTANTIATE_TEST_SUITE_P(Twins, VerdictTwinTest, ::testing::ValuesIn(testing::verdict_twins()),
                         [](const ::testing::TestParamInfo<VerdictTwin>& p) {
                             std::string n = p.param.name;
                             std::replace_if(n.begin(), n.end(), [](char c) { return !std::isalnum(c); }, '_');
                             return n;
                         });

TEST(EquivalentWarps, PassEveryDefaultCheck) {
    for (const auto& [name, make] : testing::equivalent_warps()) {
        const RunResult run = run_default_suite(make(name));
        for (const auto& r : run.results)
            EXPECT_EQ(r.verdict, Verdict::Pass) << name << " " << r.check_name << ": " << r.message;
    }
}

TEST(RoundtripRule, NaNInverseIsNeverExcused) {
    const auto warp = testing::twins::sphere("sphere_nan", true);
    const CheckResult r = testing::run_check(*make_roundtrip_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_GT(*r.figure("outside_input_domain"), 0.0);
    EXPECT_TRUE(std::isnan(*r.figure("max_error")) || std::isnan(*r.figure("max_edge_error")));
}

TEST(RoundtripRule, OtherPreimagesOfAPositiveMeasureSetFail) {
    const auto warp = testing::twins::steep_exponential("steep", true);
    const CheckResult r = testing::run_check(*make_roundtrip_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_GT(*r.figure("other_preimage_random_inputs"), *r.figure("other_preimage_bound"));
    EXPECT_NE(r.message.find("another preimage"), std::string::npos) << r.message;
}

TEST(TabulatedRule, MassBeyondTheSamplesReachFails) {
    const auto warp = testing::twins::ramp("short_ramp", false, 0.99976f);
    const CheckResult r = testing::run_check(*make_tabulated_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_NEAR(*r.figure("mass_outside_reach"), 1.0 - 0.99976 * 0.99976, 1e-6);
    EXPECT_NE(r.message.find("reach only"), std::string::npos) << r.message;
    const auto twin = testing::twins::ramp("ramp", false);
    const CheckResult ok = testing::run_check(*make_tabulated_check(), *twin);
    EXPECT_LE(*ok.figure("mass_outside_reach"), *ok.figure("mass_outside_reach_tolerance"));
}

TEST(Inputs, EdgesEnterEveryBinadeDownToTheSmallestDenormal) {
    const std::vector<float> e = edge_values();
    for (int k = 1; k <= 149; ++k)
        EXPECT_NE(std::find(e.begin(), e.end(), std::ldexp(1.0f, -k)), e.end()) << "2^-" << k;
    EXPECT_NE(std::find(e.begin(), e.end(), 0x1p-32f), e.end());
    EXPECT_NE(std::find(e.begin(), e.end(), 0x1.fffffep-1f), e.end());
    EXPECT_NE(std::find(e.begin(), e.end(), 0.0f), e.end());
    for (float v : e) EXPECT_TRUE(v >= 0.0f && v < 1.0f) << v;
}

TEST(Inputs, RandomUniformsReachBelowTheTwoToTheMinus24Grid) {
    // Every float of [2^-40, 1) has its true probability: 2^-24 is not a floor.
    EXPECT_EQ(uniform_float_from_bits(0), 0.0f);
    EXPECT_EQ(uniform_float_from_bits(~uint64_t{0}), 0x1.fffffep-1f);
    EXPECT_EQ(uniform_float_from_bits(uint64_t{1} << 32), 0x1p-32f);
    EXPECT_EQ(uniform_float_from_bits((uint64_t{1} << 40) + 1), 0x1p-24f);  // rounded down
    Pcg32 rng(1, 54);
    std::vector<WarpInput> in(1 << 16);
    draw_inputs(rng, InputKind::Uniform1D, in);
    const auto below = std::count_if(in.begin(), in.end(), [](const WarpInput& w) { return w.u[0] < 0x1p-10f; });
    const auto off_grid = std::count_if(in.begin(), in.end(), [](const WarpInput& w) {
        return w.u[0] != std::ldexp(std::floor(std::ldexp(w.u[0], 24)), -24);
    });
    EXPECT_GT(below, 30);     // 64 expected
    EXPECT_GT(off_grid, 500);  // inputs below 2^-1 have more bits than the 2^-24 grid
}

}  // namespace
}  // namespace warpcheck

namespace warpcheck {
namespace {

// A renderer's warp without an inverse (visible normals, table-driven samplers):
// the round-trip checks do not apply, everything else runs and passes.
TEST(NoInverse, RoundTripDoesNotApplyAndTheRestPasses) {
    struct DiskWithoutInverse {
        Point2f sample(Point2f u) const { return testing::twins::polar_disk(u, 1.0f); }
        float pdf(Point2f p) const { return testing::twins::disk_pdf(p); }
    };
    auto warp = make_warp_case({.family = "disk_without_inverse", .description = "no inverse",
                                .domain = chi2::Domain::unit_disk()},
                               DiskWithoutInverse{});
    EXPECT_FALSE(warp->has_inverse());
    auto lambdas = make_warp_case({.family = "disk_lambdas", .domain = chi2::Domain::unit_disk()},
                                  warp_of([](Point2f u) { return testing::twins::polar_disk(u, 1.0f); })
                                      .with_pdf(testing::twins::disk_pdf));
    EXPECT_FALSE(lambdas->has_inverse());
    std::vector<WarpOutput> x(1);
    std::vector<WarpInput> back(1);
    EXPECT_THROW(warp->invert(x, back), std::logic_error);

    const RunResult run = run_default_suite(std::move(warp));
    ASSERT_FALSE(run.results.empty());
    int not_applicable = 0;
    for (const auto& r : run.results) {
        // The round trip is shown as not applicable, with the reason; it is no
        // statistical test, so it stays out of the multiple-testing family.
        const Verdict expected = r.check_name == "roundtrip" ? Verdict::NotApplicable : Verdict::Pass;
        EXPECT_EQ(r.verdict, expected) << r.check_name << ": " << r.message;
        if (r.verdict == Verdict::NotApplicable) {
            ++not_applicable;
            EXPECT_EQ(r.summary, "not applicable: the warp has no inverse");
            EXPECT_FALSE(r.p_value.has_value());
        }
    }
    EXPECT_EQ(not_applicable, 1);
    EXPECT_TRUE(run.all_passed());
    int p_values = 0;
    for (const auto& r : run.results) p_values += r.p_value.has_value();
    EXPECT_EQ(run.info.statistical_tests, p_values);
}

// A known-flaw mark on one check leaves that check out and runs the others;
// --include-flawed (or naming the case) runs it too.
TEST(KnownFlaw, MarkOnOneCheckLeavesOnlyThatCheckOut) {
    Registry registry;
    register_builtin_checks(registry);
    registry.add_case(make_warp_case({.family = "disk_flawed_roundtrip", .domain = chi2::Domain::unit_disk()},
                                     warp_of([](Point2f u) { return testing::twins::polar_disk(u, 1.0f); })
                                         .with_pdf(testing::twins::disk_pdf)
                                         .with_invert([](Point2f) { return Point2f{0.5f, 0.5f}; })));
    registry.mark_known_flaw("disk_flawed_roundtrip", "roundtrip", "an inverse under repair");
    EXPECT_THROW(registry.mark_known_flaw("disk_flawed_roundtrip", "no_such_check", "x"), std::invalid_argument);
    RunOptions options;
    const auto checks_of = [&](const std::vector<Job>& jobs) {
        std::vector<std::string> names;
        for (const Job& j : jobs) names.push_back(j.check->name());
        return names;
    };
    const auto plain = checks_of(select_jobs(registry, {}, {}, options));
    EXPECT_EQ(std::count(plain.begin(), plain.end(), "roundtrip"), 0);
    EXPECT_EQ(std::count(plain.begin(), plain.end(), "chi2"), 1);
    options.include_flawed = true;
    const auto flawed = checks_of(select_jobs(registry, {}, {}, options));
    EXPECT_EQ(std::count(flawed.begin(), flawed.end(), "roundtrip"), 1);
    EXPECT_EQ(registry.known_flaw(*registry.cases()[0]), "");
}

}  // namespace
}  // namespace warpcheck
