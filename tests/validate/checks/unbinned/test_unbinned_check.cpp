// The "unbinned" check and the localised statistic of the "chi2" check against
// warps whose claimed density is subtly wrong: the cos^(1+eps) claim on
// the concentric cosine hemisphere, and a sampler with a small excess in one
// cell. Each is run over 10 seeds at the level of a one-case run of the default
// suite (chi2 and unbinned: the Sidak level for 2 tests at alpha = 0.01), and
// its detection rate is printed and asserted.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "chi2/local_residual.h"
#include "chi2/multiple_testing.h"
#include "sampling/hemisphere.h"
#include "sampling/sphere.h"
#include "validate/checks/check.h"
#include "validate/checks/checks.h"
#include "validate/run/runner.h"
#include "validate/run/thread_pool.h"
#include "validate/api/warp_case.h"

namespace warpcheck {
namespace {

constexpr int kSeeds = 10;
const double kSuiteLevel = chi2::sidak_level(0.01, 2);

CheckResult unbinned_of(const Check& check, const WarpCase& warp, uint64_t seed, unsigned threads = 2) {
    RunOptions options;
    options.seed = seed;
    options.threads = threads;
    ThreadPool pool(threads);
    const CheckContext ctx(options, pool.executor(), stream_for(warp.name() + "/" + check.name(), options.seed));
    return check.run(warp, ctx);
}

double figure(const CheckResult& r, const std::string& name) {
    for (const Figure& f : r.figures)
        if (f.name == name) return f.value;
    return std::nan("");
}

/// Whether a result's p-value fails at the one-case suite level (NaN fails).
bool rejects(const CheckResult& r) { return r.verdict != Verdict::Pass || !(r.p_value.value_or(1.0) >= kSuiteLevel); }

/// The concentric cosine hemisphere whose pdf claims cos^(1 + eps) theta,
/// normalised ((2 + eps) / (2 pi) z^(1 + eps) integrates to 1): only the shape is wrong.
std::unique_ptr<WarpCase> cosine_claiming_power(double eps) {
    WarpCaseInfo info;
    info.family = "cosine_hemisphere_claiming_cos_power";
    info.params = {{"eps", eps}};
    info.domain = chi2::Domain::hemisphere();
    return make_warp_case(
        info,
            warp_of([](Point2f u) { return CosineHemisphere{}.sample(u); })
                .with_pdf([eps](Vector3f v) {
                    return v.z >= 0.0f ? (2.0 + eps) / (2.0 * std::numbers::pi) * std::pow(double(v.z), 1.0 + eps) : 0.0;
                })
                .with_invert([](Vector3f v) { return CosineHemisphere{}.invert(v); }));
}

/// Detections over kSeeds seeds by the default suite's statistical checks.
int suite_detections(const WarpCase& warp) {
    const auto chi2 = make_chi2_check();
    const auto unbinned = make_unbinned_check();
    int caught = 0;
    for (uint64_t seed = 1; seed <= kSeeds; ++seed)
        caught += rejects(unbinned_of(*chi2, warp, seed)) || rejects(unbinned_of(*unbinned, warp, seed));
    return caught;
}

TEST(UnbinnedCheck, CatchesTheCosinePowerClaimAndPassesTheTrueDensity) {
    const int wrong = suite_detections(*cosine_claiming_power(0.01));
    const int right = suite_detections(*cosine_claiming_power(0.0));
    std::printf("cos^(1+eps), eps = 0.01: caught in %d of %d seeds; eps = 0: caught in %d of %d\n", wrong, kSeeds,
                right, kSeeds);
    EXPECT_GE(wrong, 9);
    EXPECT_LE(right, 1);
}

/// Uniform on [0, 1] but for an excess of about 200 q (relative) in the one
/// chi2 cell [0.5, 0.505] of the default 200: the density (1 - q) + q / 0.005
/// there, sampled by its inverse CDF, while the pdf claims 1 everywhere.
std::unique_ptr<WarpCase> uniform_with_bump(double q) {
    WarpCaseInfo info;
    info.family = "uniform_with_bump";
    info.params = {{"q", q}};
    info.domain = chi2::Domain::interval(0.0, 1.0);
    constexpr double a = 0.5, w = 0.005;
    auto cdf = [q](double x) { return (1.0 - q) * x + q * std::clamp((x - a) / w, 0.0, 1.0); };
    auto sample = [q](float u) {
        const double lo = (1.0 - q) * a, hi = lo + (1.0 - q) * w + q;
        if (u < lo) return static_cast<float>(u / (1.0 - q));
        if (u < hi) return static_cast<float>(a + (u - lo) / ((1.0 - q) + q / w));
        return static_cast<float>((u - q) / (1.0 - q));
    };
    return make_warp_case(
        info, warp_of(sample)
                  .with_pdf([](float) { return 1.0f; })
                  .with_invert([cdf](float x) { return static_cast<float>(cdf(x)); }));
}

TEST(LocalResidual, CatchesAOneCellExcessThatPearsonMisses) {
    const auto bumped = uniform_with_bump(0.00045);  // +9% in one cell: 6.4 standard deviations of its count
    const auto chi2 = make_chi2_check();
    int pearson = 0, local = 0;
    for (uint64_t seed = 1; seed <= kSeeds; ++seed) {
        const CheckResult r = unbinned_of(*chi2, *bumped, seed);
        pearson += !(figure(r, "p_value") >= (1.0 - chi2::kLocalLevelShare) * kSuiteLevel);
        local += !(figure(r, "local_p_value") >= chi2::kLocalLevelShare * kSuiteLevel);
        EXPECT_TRUE(rejects(r));
        EXPECT_EQ(figure(r, "local_cell"), 100.0);
    }
    std::printf("one-cell +9%% excess: Pearson caught it in %d of %d seeds, the largest residual in %d\n", pearson,
                kSeeds, local);
    EXPECT_GE(local, 9);  // and the check as a whole, at the suite level: EXPECT_TRUE(rejects(r)) above
    EXPECT_LE(pearson, 4);
}

TEST(UnbinnedCheck, SameFiguresForAnyThreadCount) {
    // An ordinary case and one tested against float bands (a tiny cone).
    const auto cone = make_warp_case(
        {"tiny_cone", {}, "", InputKind::Uniform2D, chi2::Domain::spherical_cap(0.99999)},
        warp_of([](Point2f u) { return UniformCone(0.99999f).sample(u); })
            .with_pdf([](Vector3f v) { return UniformCone(0.99999f).pdf(v); }));
    const auto cosine = cosine_claiming_power(0.0);
    const auto check = make_unbinned_check();
    for (const WarpCase* warp : {cosine.get(), cone.get()}) {
        const CheckResult one = unbinned_of(*check, *warp, 3, 1);
        const CheckResult four = unbinned_of(*check, *warp, 3, 4);
        ASSERT_EQ(one.figures.size(), four.figures.size());
        for (std::size_t i = 0; i < one.figures.size(); ++i) {
            EXPECT_EQ(one.figures[i].name, four.figures[i].name);
            EXPECT_EQ(std::bit_cast<uint64_t>(one.figures[i].value), std::bit_cast<uint64_t>(four.figures[i].value))
                << one.figures[i].name;
        }
        EXPECT_EQ(one.summary, four.summary);
    }
}

/// A hemisphere warp whose samples are NaN everywhere; its pdf NaN too, or
/// the uniform hemisphere's.
std::unique_ptr<WarpCase> nan_warp(const std::string& name, bool nan_pdf) {
    WarpCaseInfo info;
    info.family = name;
    info.domain = chi2::Domain::hemisphere();
    const float nan = std::nanf("");
    return make_warp_case(
        info, warp_of([nan](Point2f) { return Vector3f{nan, nan, nan}; })
                  .with_pdf([nan_pdf](Vector3f) { return nan_pdf ? std::nan("") : 1.0 / (2.0 * std::numbers::pi); }));
}

TEST(UnbinnedVerdicts, EverySampleNaNIsAFailureThatSaysSo) {
    // Today: an ERROR "the density integrates to nan" (NaN pdf), or a FAIL
    // "p-value is NaN". Either way it must be a FAIL that names the cause,
    // in the check and through the runner.
    const auto check = make_unbinned_check();
    for (bool nan_pdf : {true, false}) {
        const auto warp = nan_warp(nan_pdf ? "all_nan" : "all_nan_samples", nan_pdf);
        const CheckResult r = unbinned_of(*check, *warp, 1);
        EXPECT_EQ(r.verdict, Verdict::Fail) << r.summary;
        EXPECT_EQ(r.summary, "every sample has a NaN coordinate");
        EXPECT_NE(r.message.find("every sample has a NaN coordinate"), std::string::npos) << r.message;
        EXPECT_FALSE(r.p_value.has_value());
        RunOptions options;
        options.samples = 100'000;
        options.threads = 2;
        const RunResult run = run_jobs({{warp.get(), check.get()}}, options);
        EXPECT_EQ(run.results[0].verdict, Verdict::Fail);
        EXPECT_EQ(run.results[0].summary, "every sample has a NaN coordinate");
    }
}

TEST(UnbinnedVerdicts, AnyShareOfNaNSamplesFailsWithItsCount) {
    // Before: 1% NaN points were left out and carried into the band (a pass),
    // 90% made the CDF band too wide to test ("not applicable"). A sampler
    // that returns NaN is wrong whatever the share, as chi2 judges it: FAIL
    // with the count; ten in 10^6 fail as surely as 90%.
    const auto check = make_unbinned_check();
    for (const float share : {0.9f, 0.01f, 1e-5f}) {
        const auto warp = make_warp_case(
            {"some_nan", {{"share", share}}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
            warp_of([share](Point2f u) {
                const float nan = std::nanf("");
                return u.x < share ? Vector3f{nan, nan, nan} : UniformHemisphere{}.sample(u);
            }).with_pdf([](Vector3f v) { return UniformHemisphere{}.pdf(v); }));
        const CheckResult r = unbinned_of(*check, *warp, 1);
        SCOPED_TRACE(share);
        EXPECT_EQ(r.verdict, Verdict::Fail) << r.summary;
        EXPECT_FALSE(r.p_value.has_value());
        const double count = figure(r, "nan_samples");
        EXPECT_NEAR(count, share * 1e6, 5.0 * std::sqrt(share * 1e6) + 2.0);
        EXPECT_GE(count, 1.0);
        EXPECT_EQ(r.summary, fmt::format("{} of 1000000 samples have NaN coordinates", static_cast<uint64_t>(count)));
    }
    // The control: the same warp without NaN passes, and counts none.
    const auto clean = make_warp_case({"no_nan", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                                      warp_of([](Point2f u) { return UniformHemisphere{}.sample(u); })
                                          .with_pdf([](Vector3f v) { return UniformHemisphere{}.pdf(v); }));
    const CheckResult r = unbinned_of(*check, *clean, 1);
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.summary;
    EXPECT_EQ(figure(r, "nan_samples"), 0.0);
}

/// The uniform hemisphere whose pdf claims 1.5 times its density: each
/// marginal's tabulated total is 1.5, an error of 0.5 in the CDF, so no
/// marginal can be tested (whether the pdf integrates to 1 is the chi2
/// check's rule).
std::unique_ptr<WarpCase> overweight_hemisphere() {
    return make_warp_case({"overweight_hemisphere", {}, "", InputKind::Uniform2D, chi2::Domain::hemisphere()},
                          warp_of([](Point2f u) { return UniformHemisphere{}.sample(u); })
                              .with_pdf([](Vector3f v) { return 1.5 * UniformHemisphere{}.pdf(v); }));
}

TEST(UnbinnedVerdicts, NothingTestedIsNotApplicableAndStillCountsInTheFamily) {
    // Today: "pass" with the summary "not applicable: ...".
    const auto check = make_unbinned_check();
    const auto warp = overweight_hemisphere();
    const CheckResult r = unbinned_of(*check, *warp, 1);
    EXPECT_EQ(r.verdict, Verdict::NotApplicable);
    EXPECT_EQ(r.summary.rfind("not applicable: no marginal CDF accurate enough; untested: phi (CDF error 0.5)", 0), 0u)
        << r.summary;
    EXPECT_FALSE(r.p_value.has_value());
    EXPECT_EQ(figure(r, "untested_marginals"), 2.0);
    // The family is fixed before the results: the n/a row still counts, and
    // the other row is judged at the level of two tests.
    const auto fine = cosine_claiming_power(0.0);
    RunOptions options;
    options.samples = 100'000;
    options.threads = 2;
    const RunResult run = run_jobs({{warp.get(), check.get()}, {fine.get(), check.get()}}, options);
    EXPECT_EQ(run.results[0].verdict, Verdict::NotApplicable);
    EXPECT_FALSE(run.results[0].level.has_value());
    EXPECT_EQ(run.results[1].verdict, Verdict::Pass);
    EXPECT_EQ(run.info.statistical_tests, 2);
    EXPECT_EQ(run.results[1].level, chi2::sidak_level(0.01, 2));
    EXPECT_TRUE(run.all_passed());
}

TEST(UnbinnedVerdicts, NoRowSaysNaN) {
    // Passing (exact, banded, with samples left out), not applicable, and
    // failing-by-p-value rows alike write every number out, never "nan".
    const auto check = make_unbinned_check();
    const auto cone = make_warp_case(
        {"tiny_cone", {}, "", InputKind::Uniform2D, chi2::Domain::spherical_cap(0.99999)},
        warp_of([](Point2f u) { return UniformCone(0.99999f).sample(u); })
            .with_pdf([](Vector3f v) { return UniformCone(0.99999f).pdf(v); }));
    const std::unique_ptr<WarpCase> warps[] = {cosine_claiming_power(0.0), cosine_claiming_power(0.2),
                                               overweight_hemisphere()};
    for (const WarpCase* w : {warps[0].get(), warps[1].get(), warps[2].get(), cone.get()}) {
        const CheckResult r = unbinned_of(*check, *w, 2);
        EXPECT_TRUE(r.verdict == Verdict::Pass || r.verdict == Verdict::NotApplicable) << w->name();
        std::string text = r.summary + " " + r.message;
        std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
        EXPECT_EQ(text.find("nan"), std::string::npos) << w->name() << ": " << r.summary;
    }
}

}  // namespace
}  // namespace warpcheck
