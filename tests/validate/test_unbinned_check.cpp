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

#include <gtest/gtest.h>

#include "chi2/local_residual.h"
#include "chi2/multiple_testing.h"
#include "sampling/hemisphere.h"
#include "validate/check.h"
#include "validate/checks/checks.h"
#include "validate/thread_pool.h"
#include "validate/warp_case.h"

namespace warpcheck {
namespace {

constexpr int kSeeds = 10;
const double kSuiteLevel = chi2::sidak_level(0.01, 2);

CheckResult run_check(const Check& check, const WarpCase& warp, uint64_t seed, unsigned threads = 2) {
    RunOptions options;
    options.seed = seed;
    options.threads = threads;
    ThreadPool pool(threads);
    const CheckContext ctx(options, pool, stream_for(warp.name() + "/" + check.name(), options.seed));
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
        info, [](Point2f u) { return CosineHemisphere{}.sample(u); },
        [eps](Vector3f v) {
            return v.z >= 0.0f ? (2.0 + eps) / (2.0 * std::numbers::pi) * std::pow(double(v.z), 1.0 + eps) : 0.0;
        },
        [](Vector3f v) { return CosineHemisphere{}.invert(v); });
}

/// Detections over kSeeds seeds by the default suite's statistical checks.
int suite_detections(const WarpCase& warp) {
    const auto chi2 = make_chi2_check();
    const auto unbinned = make_unbinned_check();
    int caught = 0;
    for (uint64_t seed = 1; seed <= kSeeds; ++seed)
        caught += rejects(run_check(*chi2, warp, seed)) || rejects(run_check(*unbinned, warp, seed));
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
    info.input = InputKind::Uniform1D;
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
        info, sample, [](float) { return 1.0f; }, [cdf](float x) { return static_cast<float>(cdf(x)); });
}

TEST(LocalResidual, CatchesAOneCellExcessThatPearsonMisses) {
    const auto bumped = uniform_with_bump(0.00045);  // +9% in one cell: 6.4 standard deviations of its count
    const auto chi2 = make_chi2_check();
    int pearson = 0, local = 0;
    for (uint64_t seed = 1; seed <= kSeeds; ++seed) {
        const CheckResult r = run_check(*chi2, *bumped, seed);
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
    const auto warp = cosine_claiming_power(0.0);
    const auto check = make_unbinned_check();
    const CheckResult one = run_check(*check, *warp, 3, 1);
    const CheckResult four = run_check(*check, *warp, 3, 4);
    ASSERT_EQ(one.figures.size(), four.figures.size());
    for (std::size_t i = 0; i < one.figures.size(); ++i) {
        EXPECT_EQ(one.figures[i].name, four.figures[i].name);
        EXPECT_EQ(std::bit_cast<uint64_t>(one.figures[i].value), std::bit_cast<uint64_t>(four.figures[i].value))
            << one.figures[i].name;
    }
}

}  // namespace
}  // namespace warpcheck
