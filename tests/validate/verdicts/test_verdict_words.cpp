// Issue 22, class 8: the words of a verdict. A warp that returns NaN
// everywhere fails (it is not an error of the tool); no passing row shows a
// NaN; and the known-flaw catalogue agrees with the rules: every case marked
// as a flaw fails by them.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <limits>
#include <string>

#include "support/check_harness.h"
#include "validate/checks/checks.h"
#include "validate/api/registry.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

using testing::run_check;
constexpr float kWordsNaN = std::numeric_limits<float>::quiet_NaN();

/// Every check of `makers` that applies to the warp must FAIL (not ERROR), with a message that names NaN.
void expect_nan_fails(const WarpCase& warp, std::initializer_list<std::unique_ptr<Check> (*)()> makers) {
    for (auto make : makers) {
        const auto check = make();
        ASSERT_TRUE(check->applies_to(warp)) << check->name();
        const CheckResult r = run_check(*check, warp, 100'000);
        EXPECT_EQ(r.verdict, Verdict::Fail) << check->name() << ": " << r.summary << " / " << r.message;
        std::string text = r.summary + " " + r.message;
        for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        EXPECT_TRUE(text.find("nan") != std::string::npos || text.find("non-finite") != std::string::npos)
            << check->name() << ": " << r.summary << " / " << r.message;
        EXPECT_EQ(text.find("discontinuous"), std::string::npos) << check->name() << ": " << r.message;
    }
}

TEST(NaNEverywhere, PointsAndPdfFailConsistency) {
    auto warp = make_warp_case({.family = "nan_everywhere"},
        warp_of([](Point2f) { return Point2f{kWordsNaN, kWordsNaN}; }).with_pdf([](Point2f) { return kWordsNaN; }));
    expect_nan_fails(*warp, {make_consistency_check});
}

TEST(NaNEverywhere, ReturnedPdfFailsConsistencyAndTheMeanOfItsInverse) {
    auto warp = make_warp_case({.family = "nan_returned_pdf"},
                               warp_of([](Point2f) { return PdfSample<Point2f>{{kWordsNaN, kWordsNaN}, kWordsNaN}; }));
    expect_nan_fails(*warp, {make_consistency_check, make_inverse_pdf_mean_check});
}

TEST(NaNEverywhere, WeightedSamplerFailsTheMeanWeight) {
    auto warp = make_warp_case({.family = "nan_weighted", .domain = chi2::Domain::hemisphere()},
                                   warp_of([](Point2f) { return WeightedSample<Vector3f>{{kWordsNaN, kWordsNaN, kWordsNaN}, kWordsNaN}; })
                                       .with_pdf([](Vector3f) { return kWordsNaN; })
                                       .with_eval([](Vector3f) { return kWordsNaN; }));
    expect_nan_fails(*warp, {make_consistency_check, make_weight_mean_check});
}

TEST(NaNEverywhere, DiscreteSamplerFailsItsChecks) {
    auto warp = make_warp_case({.family = "nan_discrete", .categories = 4},
                               warp_of([](float) { return DiscreteSample{0, kWordsNaN}; })
                                   .with_pdf([](uint32_t) { return kWordsNaN; }));
    expect_nan_fails(*warp, {make_pmf_check, make_discrete_chi2_check, make_remapped_u_check});
}

TEST(NaNEverywhere, FloatSamplersFailTheirChecks) {
    auto bits64 = make_warp_case({.family = "nan_bits64", .domain = chi2::Domain::interval(0, 1)},
                                 warp_of([](uint64_t) { return kWordsNaN; }).with_pdf([](float) { return kWordsNaN; }));
    expect_nan_fails(*bits64, {make_binade_check, make_consistency_check});
}

}  // namespace
}  // namespace warpcheck

namespace warpcheck {
namespace {

// A discrete sampler with one category of positive pmf: its counts have no
// degrees of freedom, and the row says what was tested instead of "chi2 nan".
TEST(NothingTested, DiscreteCountsWithoutDegreesOfFreedomSaySo) {
    auto one = make_warp_case({.family = "one_category", .categories = 3},
                              warp_of([](float) { return 1; })
                                  .with_pdf([](int i) { return i == 1 ? 1.0f : 0.0f; }));
    const CheckResult r = run_check(*make_discrete_chi2_check(), *one);
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.summary;
    EXPECT_EQ(r.summary.find("nan"), std::string::npos) << r.summary;
    EXPECT_NE(r.summary.find("no degrees of freedom"), std::string::npos) << r.summary;
    // The twin picks a category of pmf 0 for 1% of its inputs.
    auto wrong = make_warp_case({.family = "one_category_wrong", .categories = 3},
                                warp_of([](float u) { return u < 0.01f ? 2 : 1; })
                                    .with_pdf([](int i) { return i == 1 ? 1.0f : 0.0f; }));
    EXPECT_EQ(run_check(*make_discrete_chi2_check(), *wrong).verdict, Verdict::Fail);
}

// The catalogue of known flaws agrees with the rules: each case marked as a
// flaw fails some default check when run. lerp_blend[a=1,b=3] was marked
// ("steps down, and can reach b") while it passed every check: it does not
// claim monotonicity and stays inside [1, 3), so it left the catalogue.
TEST(KnownFlaws, EveryMarkedCaseFailsByTheRules) {
    Registry registry;
    register_builtin_checks(registry);
    register_flawed_interval_cases(registry);
    RunOptions options;
    options.threads = 2;
    options.samples = 100'000;
    options.include_flawed = true;
    options.check_time_budget = testing::kTestTimeBudget;
    const RunResult run = run_jobs(select_jobs(registry, {}, {}, options), options);
    ASSERT_GE(registry.cases().size(), 7u);
    for (const auto& warp : registry.cases()) {
        const std::string flaw = registry.known_flaw(*warp);
        EXPECT_FALSE(flaw.empty()) << warp->name() << " is registered with the flaws but not marked";
        int failed = 0;
        for (const CheckResult& r : run.results) failed += r.case_name == warp->name() && r.verdict == Verdict::Fail;
        EXPECT_GE(failed, 1) << warp->name() << " is marked \"" << flaw << "\" but passes every check";
    }
    EXPECT_EQ(registry.find_case("lerp_blend[a=1,b=3]"), nullptr);
}

}  // namespace
}  // namespace warpcheck
