// The "chi2" check against real warps: correct ones pass at the default sample
// count, wrong ones (density off by 2% over part of the domain, mirrored
// samples) fail, non-statistical problems fail with their own message, and the
// result is bit-identical for any thread count. Seeds are fixed, so every test
// here is deterministic.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "chi2/domain.h"
#include "sampling/exponential.h"
#include "sampling/hemisphere.h"
#include "sampling/sphere.h"
#include "sampling/trowbridge_reitz.h"
#include "support/builtin_case.h"
#include "validate/checks/check.h"
#include "validate/checks/checks.h"
#include "validate/run/thread_pool.h"
#include "validate/api/warp_case.h"
#include "sampling/math.h"

namespace warpcheck {
namespace {

// Correct warps give uniform p-values; with fixed seeds these are fixed numbers,
// and this level is far below any of them.
constexpr double kPassLevel = 1e-4;
// Wrong warps must fall below the Šidák level of any realistic run
// (alpha = 0.01 over 10^4 tests: 1.0e-6).
constexpr double kFailLevel = 1e-6;

CheckResult run_chi2(const WarpCase& warp, unsigned threads = 2, uint64_t samples = 1'000'000) {
    RunOptions options;
    options.samples = samples;
    options.threads = threads;
    ThreadPool pool(threads);
    const CheckContext ctx(options, pool.executor(), stream_for(warp.name() + "/chi2", options.seed));
    return make_chi2_check()->run(warp, ctx);
}

WarpCaseInfo info(std::string family, chi2::Domain domain) {
    WarpCaseInfo i;
    i.family = std::move(family);
    i.domain = domain;
    return i;
}

// The production cases, by name.
const WarpCase& cosine_hemisphere() { return testing::builtin_case("cosine_hemisphere"); }
const WarpCase& uniform_sphere() { return testing::builtin_case("uniform_sphere"); }

void expect_statistical_pass(const CheckResult& r) {
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
    ASSERT_TRUE(r.p_value.has_value());
    EXPECT_TRUE(*r.p_value >= kPassLevel) << *r.p_value;
}

// --- Null: correct warps pass ---------------------------------------------------

TEST(Chi2Check, CorrectGeometricWarpsPass) {
    expect_statistical_pass(run_chi2(cosine_hemisphere()));
    expect_statistical_pass(run_chi2(uniform_sphere()));
    expect_statistical_pass(run_chi2(testing::builtin_case("uniform_cone[cos_theta_max=0.3]")));
}

TEST(Chi2Check, PeakedTrowbridgeReitzPasses) {
    // alpha = 0.05: almost all mass within 1 - cos theta < 0.01, in the top
    // rows of a uniform grid: the cells move to the quantiles of a pilot
    // (equal probability, none pooled), and the quadrature finds the peak.
    const TrowbridgeReitz tr(0.05f);
    auto warp = make_warp_case(
        info("trowbridge_reitz_normals", chi2::Domain::hemisphere()),
        warp_of([tr](Point2f u) { return tr.normals().sample(u); })
            .with_pdf([tr](Vector3f m) { return tr.D(m) * std::max(0.0f, m.z); })
            .with_invert([](Vector3f) { return Point2f{}; }));
    const CheckResult r = run_chi2(*warp);
    expect_statistical_pass(r);
    EXPECT_EQ(*r.figure("equal_probability_cells"), 1.0);
    EXPECT_LT(*r.figure("pooled_cells"), 10.0);
    EXPECT_LT(*r.figure("power_tilt_eps"), 0.05);
    EXPECT_NEAR(*r.figure("integral"), 1.0, 1e-4);
    EXPECT_LE(*r.figure("integration_error_ratio"), 1.0);
}

TEST(Chi2Check, ExponentialOnTheHalfLinePassesWhateverItsRate) {
    for (float rate : {1.0f, 250.0f, 0.002f}) {
        const Exponential e(rate);
        auto warp = make_warp_case(info("exponential", chi2::Domain::half_line(0.0)), e);
        const CheckResult r = run_chi2(*warp);
        expect_statistical_pass(r);
        // The cells follow the distribution's scale (1 / pdf(0) = 1 / rate).
        EXPECT_NEAR(*r.figure("half_line_scale"), 1.0 / rate, 1e-3 / rate);
        EXPECT_GT(*r.figure("dof"), 150.0) << rate;
    }
}

// --- Power: wrong warps fail at the default sample count ------------------------

TEST(Chi2Check, DensityOffByTwoPercentOverPartOfTheDomainFails) {
    // The pdf claims 2% more density where x > 0 and 2% less where x < 0 (still
    // normalised): the samples of the correct warp disagree with it.
    auto warp = make_warp_case(
        info("cosine_hemisphere_tilted_pdf", chi2::Domain::hemisphere()),
        warp_of([](Point2f u) { return CosineHemisphere{}.sample(u); })
            .with_pdf([](Vector3f v) { return (v.x > 0 ? 1.02f : 0.98f) * CosineHemisphere{}.pdf(v); })
            .with_invert([](Vector3f v) { return CosineHemisphere{}.invert(v); }));
    const CheckResult r = run_chi2(*warp);
    EXPECT_EQ(r.verdict, Verdict::Pass) << "no non-statistical failure: " << r.message;
    ASSERT_TRUE(r.p_value.has_value());
    EXPECT_LT(*r.p_value, kFailLevel);
    EXPECT_NEAR(*r.figure("integral"), 1.0, 1e-4);
}

TEST(Chi2Check, MirroredSamplesFail) {
    // Density 2x on the unit square; the broken warp mirrors x.
    const auto linear = [](bool mirrored) {
        return make_warp_case(
            info(mirrored ? "linear_mirrored" : "linear", chi2::Domain::unit_square()),
            warp_of([mirrored](Point2f u) {
                        const float x = std::sqrt(u.x);
                        return Point2f{mirrored ? 1.0f - x : x, u.y};
                    })
                .with_pdf([](Point2f p) { return 2.0f * p.x; })
                .with_invert([](Point2f p) { return Point2f{p.x * p.x, p.y}; }));
    };
    expect_statistical_pass(run_chi2(*linear(false)));
    const CheckResult r = run_chi2(*linear(true));
    ASSERT_TRUE(r.p_value.has_value());
    EXPECT_LT(*r.p_value, kFailLevel);
}

// --- Non-statistical failures ----------------------------------------------------

TEST(Chi2Check, DensityIntegratingToLessThanOneFailsOnItsOwn) {
    auto warp = make_warp_case(
        info("uniform_sphere_low_pdf", chi2::Domain::sphere()),
            warp_of([](Point2f u) { return UniformSphere{}.sample(u); })
                .with_pdf([](Vector3f) { return 0.99f / (4 * kPi); })
                .with_invert([](Vector3f v) { return UniformSphere{}.invert(v); }));
    const CheckResult r = run_chi2(*warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_NE(r.message.find("integrates to 0.99"), std::string::npos) << r.message;
}

TEST(Chi2Check, NaNAndOutsideSamplesFailOnTheirOwn) {
    auto warp = make_warp_case(
        info("broken_sphere", chi2::Domain::sphere()),
        warp_of([](Point2f u) {
                    Vector3f v = UniformSphere{}.sample(u);
                    if (u.x < 1e-4f) v.x = std::nanf("");
                    if (u.x > 0.9999f) v = 2.0f * v;
                    return v;
                })
            .with_pdf([](Vector3f v) { return UniformSphere{}.pdf(v); })
            .with_invert([](Vector3f v) { return UniformSphere{}.invert(v); }));
    const CheckResult r = run_chi2(*warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_GT(*r.figure("nan"), 0.0);
    EXPECT_GT(*r.figure("outside"), 0.0);
    EXPECT_NE(r.message.find("NaN"), std::string::npos);
    EXPECT_NE(r.message.find("outside the sphere"), std::string::npos);
}

// --- Result content and determinism ------------------------------------------------

TEST(Chi2Check, ResultCarriesFiguresSummaryAndPlots) {
    const CheckResult r = run_chi2(cosine_hemisphere(), 2, 200'000);
    for (const char* name : {"statistic", "dof", "p_value", "integral", "cells", "pooled_cells", "outside", "nan",
                             "zero_expected_hits"})
        EXPECT_TRUE(r.figure(name).has_value()) << name;
    EXPECT_EQ(r.summary.rfind("chi2 ", 0), 0u) << r.summary;
    EXPECT_NE(r.summary.find(" dof "), std::string::npos);
    EXPECT_EQ(r.samples, 200'000u);
    EXPECT_FALSE(r.level.has_value());  // the runner sets it
    ASSERT_EQ(r.plots.size(), 1u);
    const Plot& p = r.plots[0];
    EXPECT_EQ(p.kind, Plot::Kind::Heatmaps);
    EXPECT_EQ(p.x_label, "phi");
    EXPECT_EQ(p.y_label, "cos theta");
    ASSERT_EQ(p.heatmaps.size(), 3u);
    for (const Heatmap& h : p.heatmaps) {
        EXPECT_EQ(h.rows * h.cols, static_cast<int>(h.values.size()));
        EXPECT_EQ(h.y_min, 0.0);
        EXPECT_EQ(h.y_max, 1.0);
    }
    double observed = 0.0;
    for (double v : p.heatmaps[0].values) observed += v;
    EXPECT_EQ(observed, 200'000.0);
}

TEST(Chi2Check, OneDimensionalCasesGetLinePlots) {
    const CheckResult r = run_chi2(testing::builtin_case("exponential[a=1]"), 1, 100'000);
    ASSERT_EQ(r.plots.size(), 2u);
    EXPECT_EQ(r.plots[0].series.size(), 2u);  // observed, expected
    EXPECT_EQ(r.plots[1].series.size(), 1u);  // residual
}

TEST(Chi2Check, BitIdenticalForAnyThreadCount) {
    const WarpCase& warp = cosine_hemisphere();
    const CheckResult one = run_chi2(warp, 1, 500'000);
    for (unsigned threads : {2u, 3u}) {
        const CheckResult many = run_chi2(warp, threads, 500'000);
        ASSERT_EQ(one.figures.size(), many.figures.size());
        for (std::size_t i = 0; i < one.figures.size(); ++i) {
            EXPECT_EQ(one.figures[i].name, many.figures[i].name);
            // Bitwise, NaN included.
            EXPECT_EQ(std::bit_cast<uint64_t>(one.figures[i].value), std::bit_cast<uint64_t>(many.figures[i].value))
                << one.figures[i].name;
        }
        EXPECT_EQ(one.plots[0].heatmaps[0].values, many.plots[0].heatmaps[0].values);
        EXPECT_EQ(one.summary, many.summary);
    }
}

}  // namespace
}  // namespace warpcheck
