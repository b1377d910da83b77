// The tabulated check: where it applies, that correct warps pass with margin,
// that small sampling, density and tail errors fail with their own messages,
// and that its figures do not depend on the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "sampling/exponential.h"
#include "sampling/trowbridge_reitz.h"
#include "support/builtin_case.h"
#include "support/check_harness.h"
#include "validate/checks/checks.h"

namespace warpcheck {
namespace {

using testing::run_check;

WarpCaseInfo info_1d(const std::string& family, chi2::Domain domain) {
    WarpCaseInfo info;
    info.family = family;
    info.description = "test warp";
    info.domain = domain;
    return info;
}

/// An exponential with rate a on the half-line, truncated for the check where
/// the tail holds 1e-3; `scale` and `pdf_scale` plant errors in sample and pdf.
std::unique_ptr<WarpCase> exponential_case(float a, float scale = 1.0f, float pdf_scale = 1.0f, float clamp = 0.0f) {
    WarpCaseInfo info = info_1d("exponential", chi2::Domain::half_line(0.0));
    MonotoneMarginal m;
    m.hi = std::log(1000.0) / a;
    m.tail_mass = std::exp(-a * m.hi);
    info.views = {m};
    const Exponential e(a);
    return make_warp_case(
        info,
        warp_of([e, scale, clamp](float u) {
                    const float x = scale * e.sample(u);
                    return clamp > 0.0f ? std::min(x, clamp) : x;
                })
            .with_pdf([e, pdf_scale](float x) { return pdf_scale * e.pdf(x); })
            .with_invert([e](float x) { return e.invert(x); }));
}

/// The isotropic Trowbridge-Reitz normals with their cos(theta_m) marginal
/// declared increasing in u.x, which it is not.
std::unique_ptr<WarpCase> tr_normal_case_declared_increasing(float alpha) {
    WarpCaseInfo info;
    info.family = "trowbridge_reitz_normals_declared_increasing";
    info.domain = chi2::Domain::hemisphere();
    MonotoneMarginal m;
    m.input_coordinate = 0;
    m.increasing = true;
    m.coordinate = [](const WarpOutput& o) { return static_cast<double>(o[2]); };
    m.pdf = [alpha](double z) { return TrowbridgeReitz::isotropic_cos_theta_pdf(alpha, z); };
    info.views = {m};
    const TrowbridgeReitz tr(alpha);
    return make_warp_case(info, tr.normals());
}

TEST(TabulatedCheck, AppliesTo1DWarpsAndDeclaredMarginals) {
    const auto check = make_tabulated_check();
    const TrimmedExponential t(1.0f, 1.0f);
    auto interval = make_warp_case(info_1d("trimmed", chi2::Domain::interval(0.0, 1.0)), t);
    EXPECT_TRUE(check->applies_to(*interval));
    EXPECT_TRUE(check->applies_to(testing::builtin_case("exponential[a=1]")));
    EXPECT_TRUE(check->applies_to(testing::builtin_case("trowbridge_reitz_normals[ax=0.3,ay=0.3]")));
    // A half-line without a declared truncation, and a 2D warp without a marginal: no.
    const Exponential e(1.0f);
    auto half_line = make_warp_case(info_1d("exponential", chi2::Domain::half_line(0.0)), e);
    EXPECT_FALSE(check->applies_to(*half_line));
    WarpCaseInfo plain;
    plain.family = "plain";
    plain.domain = chi2::Domain::hemisphere();
    const TrowbridgeReitz tr(0.3f);
    auto no_marginal = make_warp_case(plain, tr.normals());
    EXPECT_FALSE(check->applies_to(*no_marginal));
}

TEST(TabulatedCheck, CorrectWarpsPassWithMarginAndReportEvidence) {
    const auto check = make_tabulated_check();
    for (const char* name : {"exponential[a=0.1]", "exponential[a=1]", "exponential[a=10]"}) {
        const CheckResult r = run_check(*check, testing::builtin_case(name));
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
        EXPECT_LE(*r.figure("max_x_error_over_tolerance"), 0.5);
        EXPECT_LE(*r.figure("max_pdf_error_over_tolerance"), 0.5);
        EXPECT_GT(*r.figure("tail_samples"), 100.0);  // ~1e-3 of 2e5 inputs test the tail
        EXPECT_NEAR(*r.figure("table_integral") + *r.figure("tail_mass"), 1.0, *r.figure("integral_tolerance"));
        ASSERT_EQ(r.plots.size(), 3u);
        EXPECT_EQ(r.plots[0].kind, Plot::Kind::Lines);
        EXPECT_EQ(r.plots[0].series.size(), 2u);  // warp and table inverse CDFs
        EXPECT_EQ(r.plots[2].series.size(), 3u);  // analytic, table, difference
        ASSERT_EQ(r.tables.size(), 1u);
        EXPECT_FALSE(r.tables[0].rows.empty());
    }
    for (const char* name : {"trowbridge_reitz_normals[ax=0.05,ay=0.05]", "trowbridge_reitz_normals[ax=0.3,ay=0.3]",
                             "trowbridge_reitz_normals[ax=1,ay=1]"}) {
        const CheckResult r = run_check(*check, testing::builtin_case(name));
        EXPECT_EQ(r.verdict, Verdict::Pass) << name << ": " << r.message;
    }
}

TEST(TabulatedCheck, SamplingErrorOfOnePartInAThousandFails) {
    const CheckResult r = run_check(*make_tabulated_check(), *exponential_case(1.0f, 1.001f));
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_GT(*r.figure("x_failures"), 0.0);
    EXPECT_NE(r.message.find("bucket bound"), std::string::npos) << r.message;
}

TEST(TabulatedCheck, DensityOffByOnePercentFails) {
    const CheckResult r = run_check(*make_tabulated_check(), *exponential_case(1.0f, 1.0f, 1.01f));
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_NE(r.message.find("integrates to"), std::string::npos) << r.message;
    EXPECT_GT(*r.figure("pdf_failures"), 0.0);
}

TEST(TabulatedCheck, MissingTailFails) {
    // A sampler that never goes beyond 90% of the truncation point.
    const float a = 1.0f;
    const CheckResult r =
        run_check(*make_tabulated_check(), *exponential_case(a, 1.0f, 1.0f, 0.9f * std::log(1000.0f) / a));
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_GT(*r.figure("tail_failures"), 0.0);
}

TEST(TabulatedCheck, WrongMonotonicityFails) {
    // cos(theta_m) decreases with u.x; declaring it increasing must not pass.
    const CheckResult r = run_check(*make_tabulated_check(), *tr_normal_case_declared_increasing(0.3f));
    EXPECT_EQ(r.verdict, Verdict::Fail);
}

TEST(TabulatedCheck, NaNSamplesFail) {
    WarpCaseInfo info = info_1d("nan", chi2::Domain::interval(0.0, 1.0));
    const TrimmedExponential t(1.0f, 1.0f);
    auto warp = make_warp_case(
        info, warp_of([t](float u) { return u > 0.7f ? std::numeric_limits<float>::quiet_NaN() : t.sample(u); })
                  .with_pdf([t](float x) { return t.pdf(x); })
                  .with_invert([t](float x) { return t.invert(x); }));
    const CheckResult r = run_check(*make_tabulated_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
}

TEST(TabulatedCheck, FiguresDoNotDependOnThreads) {
    const auto check = make_tabulated_check();
    const WarpCase& warp = testing::builtin_case("trowbridge_reitz_normals[ax=0.3,ay=0.3]");
    const CheckResult one = run_check(*check, warp, 300'000, 1);
    const CheckResult three = run_check(*check, warp, 300'000, 3);
    ASSERT_EQ(one.figures.size(), three.figures.size());
    for (std::size_t i = 0; i < one.figures.size(); ++i) {
        EXPECT_EQ(one.figures[i].name, three.figures[i].name);
        EXPECT_EQ(one.figures[i].value, three.figures[i].value) << one.figures[i].name;
    }
}

}  // namespace
}  // namespace warpcheck
