// BSDF cases and checks (issue 23): the built-in BSDFs pass every BSDF check
// on several seeds, judged as validate judges them (Sidak over the run), and
// each known-bad BSDF of the catalogue (validate/cases/bsdf_flawed.cpp) fails
// the check meant to catch it and passes every check its bug does not touch.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "support/flawed_catalogue.h"
#include "validate/api/registry.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

constexpr const char* kBsdfChecks[] = {"bsdf_chi2",        "bsdf_unbinned",    "bsdf_weight",
                                       "bsdf_delta",       "bsdf_albedo",      "bsdf_reciprocity",
                                       "bsdf_expectation", "bsdf_spectral"};

std::vector<std::string> bsdf_checks() { return {std::begin(kBsdfChecks), std::end(kBsdfChecks)}; }

RunResult run(const Registry& registry, const std::vector<std::string>& cases, uint64_t seed, uint64_t samples) {
    return testing::run_including_flawed(registry, cases, bsdf_checks(), seed, samples);
}

using testing::failures_of;

// The hardest of the default grid (the sharpest lobes at 85 degrees, the
// anisotropic lobe across its long axis, a peaky phase function, both delta
// lobes near grazing, a mixture with a delta coat) on ten seeds, a quarter of
// the default sample count to stay within ~15 s; the whole grid at the default
// count is validate --all (ctest validate_all).
TEST(BsdfBuiltins, HardestCasesPassOnTenSeeds) {
    Registry registry;
    register_builtin_cases(registry);
    register_builtin_checks(registry);
    const std::vector<std::string> cases = {
        "rough_conductor[alpha=0.05,theta_o=85]",
        "rough_conductor_aniso[ax=0.3,ay=0.05,theta_o=85,phi_o=45]",
        "rough_dielectric[alpha=0.1,eta=1.5,theta_o=85]",
        "smooth_dielectric[eta=1.5,theta_o=85]",
        "plastic[kd=0.8,eta=1.5,alpha=0,theta_o=85]",
        "henyey_greenstein[g=0.9,theta_o=30]",
        "coated_diffuse[R=0.8,eta=1.5,theta_o=85]",
        "coated_conductor[alpha=0.3,eta=1.5,theta_o=80]",
        "rgb_conductor[alpha=0.3,theta_o=30,hero=1]",
        "dispersive_dielectric[alpha=0.3,eta=1.5,theta_o=30,hero=0]",
    };
    for (uint64_t seed = 1; seed <= 10; ++seed) {
        const RunResult r = run(registry, cases, seed, 250'000);
        EXPECT_GE(r.results.size(), cases.size() * 4) << "a case of the list is no longer registered";
        EXPECT_EQ(r.count(Verdict::Fail) + r.count(Verdict::Error), 0) << "seed " << seed << failures_of(r);
    }
}

// Each known-bad BSDF at the default sample count, all in one run judged as
// `validate --include-flawed` judges it (Sidak over the run): its check fails,
// and so do only the checks its bug rightly moves; the others pass or do not
// apply.
TEST(BsdfFlawed, EachIsCaughtByItsCheckAndOnlyByTheChecksItsBugTouches) {
    Registry registry;
    register_builtin_checks(registry);
    register_flawed_bsdf_cases(registry);
    testing::expect_each_caught(registry, bsdf_flawed_catalogue(), run(registry, {}, 1, 1'000'000));
}

// The evidence across a family's grid (issue 23): each albedo row is a point
// at its theta_o on the family's albedo plot (the mean weight with its 99%
// interval, the albedo, the bound 1) and on the plot of their difference; each
// reciprocity row on the reciprocity error's; grouped by the other parameters.
TEST(BsdfEvidence, RowsArePointsOnTheirFamilysPlotsAcrossTheGrid) {
    Registry registry;
    register_builtin_cases(registry);
    register_builtin_checks(registry);
    RunOptions options;
    options.samples = 20'000;
    options.threads = 2;
    const RunResult r = run_jobs(select_jobs(registry, {"rough_conductor["}, {"bsdf_albedo", "bsdf_reciprocity"}, options),
                                 options);
    ASSERT_EQ(r.results.size(), 12u);
    for (const CheckResult& c : r.results) {
        ASSERT_FALSE(c.family_points.empty()) << c.check_name << " " << c.case_name;
        const FamilyPoint& p = c.family_points.front();
        EXPECT_EQ(p.family, "rough_conductor");
        EXPECT_NE(c.case_name.find("theta_o=" + fmt::format("{}", p.x) + "]"), std::string::npos) << c.case_name;
        EXPECT_NE(c.case_name.find(p.group), std::string::npos) << p.group;
        EXPECT_EQ(p.group.find("theta_o"), std::string::npos) << p.group;
        if (c.check_name == "bsdf_reciprocity") {
            EXPECT_TRUE(p.log_y);
            EXPECT_EQ(p.values.at(0).y, c.figure("max_relative_error"));
            continue;
        }
        ASSERT_EQ(c.family_points.size(), 2u);
        const FamilyValue& mean = p.values.at(0);
        EXPECT_EQ(mean.y, c.figure("mean_weight"));
        EXPECT_LT(mean.low, mean.y);
        EXPECT_GT(mean.high, mean.y);
        EXPECT_EQ(p.values.at(1).y, c.figure("albedo"));
        ASSERT_EQ(p.limits.size(), 1u);
        EXPECT_EQ(p.limits[0].value, 1.0);
        const FamilyValue& difference = c.family_points[1].values.at(0);
        EXPECT_DOUBLE_EQ(difference.y, mean.y - p.values[1].y);
    }
}

// The catalogue runs only when asked for: validate --all stays green.
TEST(BsdfFlawed, LeftOutOfTheDefaultRun) {
    Registry registry;
    register_builtin_checks(registry);
    register_flawed_bsdf_cases(registry);
    RunOptions options;
    EXPECT_TRUE(select_jobs(registry, {}, {}, options).empty());
    options.include_flawed = true;
    EXPECT_FALSE(select_jobs(registry, {}, {}, options).empty());
}

}  // namespace
}  // namespace warpcheck
