// The mistakes renderers make with these warps, planted on purpose: each wrong
// variant must fail the check that is meant to see it, and the correct warp
// must pass the same check under the same seed (so the test can fail both ways).
//   - Trowbridge-Reitz D with alpha in place of alpha^2;
//   - the trimmed exponential normalised as if untrimmed;
//   - the visible-normal density with |wo.wm| in place of the mask max(0, wo.wm).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "sampling/exponential.h"
#include "sampling/trowbridge_reitz.h"
#include "support/check_harness.h"
#include "validate/checks/checks.h"

namespace warpcheck {
namespace {

using testing::run_check;

// --- Trowbridge-Reitz with alpha in place of alpha^2 ---------------------------

/// D written with the classic typo: alpha / (pi cos^4 (alpha + tan^2)^2) instead
/// of alpha^2 / (pi cos^4 (alpha^2 + tan^2)^2). `wrong` false gives the right D.
double isotropic_D(double alpha, double z, bool wrong) {
    const double a = wrong ? alpha : alpha * alpha;
    const double c2 = z * z, tan2 = (1.0 - c2) / c2;
    return a / (std::numbers::pi * c2 * c2 * (a + tan2) * (a + tan2));
}

std::unique_ptr<WarpCase> tr_normals(float alpha, bool wrong) {
    WarpCaseInfo info;
    info.family = wrong ? "trowbridge_reitz_normals_alpha_not_squared" : "trowbridge_reitz_normals";
    info.params = {{"ax", alpha}, {"ay", alpha}};
    info.domain = chi2::Domain::hemisphere();
    // The marginal of cos(theta_m) as its author would derive it from D: 2 pi z D(z).
    MonotoneMarginal m;
    m.increasing = false;
    m.coordinate = [](const WarpOutput& o) { return static_cast<double>(o[2]); };
    m.pdf = [alpha, wrong](double z) { return z > 0.0 ? 2.0 * std::numbers::pi * z * isotropic_D(alpha, z, wrong) : 0.0; };
    info.marginal = m;
    const TrowbridgeReitz tr(alpha);
    return make_warp_case(
        info, [tr](Point2f u) { return tr.sample_normal(u); },
        [alpha, wrong](Vector3f w) { return w.z > 0.0f ? isotropic_D(alpha, w.z, wrong) * w.z : 0.0; },
        [tr](Vector3f w) { return tr.invert_normal(w); });
}

TEST(WrongVariants, TrowbridgeReitzAlphaInPlaceOfAlphaSquared) {
    const auto tabulated = make_tabulated_check();
    const auto chi2 = make_chi2_check();
    for (float alpha : {0.05f, 0.3f}) {
        const auto good = tr_normals(alpha, false), bad = tr_normals(alpha, true);
        const CheckResult good_tab = run_check(*tabulated, *good), bad_tab = run_check(*tabulated, *bad);
        EXPECT_EQ(good_tab.verdict, Verdict::Pass) << alpha << ": " << good_tab.message;
        EXPECT_EQ(bad_tab.verdict, Verdict::Fail) << alpha;
        const CheckResult good_chi2 = run_check(*chi2, *good), bad_chi2 = run_check(*chi2, *bad);
        EXPECT_EQ(good_chi2.verdict, Verdict::Pass) << alpha << ": " << good_chi2.message;
        EXPECT_EQ(bad_chi2.verdict, Verdict::Fail) << alpha;
    }
}

// --- Trimmed exponential normalised as if untrimmed ------------------------------

std::unique_ptr<WarpCase> trimmed(float c, float x_max, bool wrong) {
    WarpCaseInfo info;
    info.family = wrong ? "trimmed_exponential_untrimmed_norm" : "trimmed_exponential";
    info.params = {{"c", c}, {"x_max", x_max}};
    info.input = InputKind::Uniform1D;
    info.domain = chi2::Domain::interval(0.0, x_max);
    const TrimmedExponential t(c, x_max);
    return make_warp_case(
        info, [t](float u) { return t.sample(u); },
        [t, wrong](float x) {
            // The bug: c exp(-c x), forgetting the 1 / (1 - exp(-c x_max)) of the trimming.
            return wrong ? (x >= 0.0f && x <= t.x_max() ? t.rate() * std::exp(-t.rate() * x) : 0.0f) : t.pdf(x);
        },
        [t](float x) { return t.invert(x); });
}

TEST(WrongVariants, TrimmedExponentialNormalisedAsIfUntrimmed) {
    const auto tabulated = make_tabulated_check();
    const auto chi2 = make_chi2_check();
    for (auto [c, x_max] : {std::pair{1.0f, 1.0f}, {0.5f, 4.0f}}) {
        const auto good = trimmed(c, x_max, false), bad = trimmed(c, x_max, true);
        const CheckResult good_tab = run_check(*tabulated, *good), bad_tab = run_check(*tabulated, *bad);
        EXPECT_EQ(good_tab.verdict, Verdict::Pass) << good_tab.message;
        EXPECT_EQ(bad_tab.verdict, Verdict::Fail);
        EXPECT_NE(bad_tab.message.find("integrates to"), std::string::npos) << bad_tab.message;
        const CheckResult good_chi2 = run_check(*chi2, *good), bad_chi2 = run_check(*chi2, *bad);
        EXPECT_EQ(good_chi2.verdict, Verdict::Pass) << good_chi2.message;
        EXPECT_EQ(bad_chi2.verdict, Verdict::Fail);
    }
}

// --- Visible normals with |wo.wm| instead of the mask ----------------------------

std::unique_ptr<WarpCase> visible(float alpha, double theta_o_degrees, bool wrong) {
    WarpCaseInfo info;
    info.family = wrong ? "trowbridge_reitz_visible_abs_dot" : "trowbridge_reitz_visible";
    info.params = {{"ax", alpha}, {"ay", alpha}, {"theta_o", theta_o_degrees}};
    info.domain = chi2::Domain::hemisphere();
    const double t = theta_o_degrees * std::numbers::pi / 180.0;
    const TrowbridgeReitz tr(alpha);
    const auto vis = tr.visible_normals({static_cast<float>(std::sin(t)), 0.0f, static_cast<float>(std::cos(t))});
    return make_warp_case(
        info, [vis](Point2f u) { return vis.sample(u); },
        [vis, wrong](Vector3f w) {
            if (!wrong) return vis.pdf(w);
            // The bug: |wo.wm| lets back-facing normals into the density, which
            // then integrates to more than 1 (the samples never go there).
            const TrowbridgeReitz& d = vis.distribution();
            return w.z >= 0.0f ? d.G1_over_cos(vis.wo()) * std::abs(dot(vis.wo(), w)) * d.D(w) : 0.0f;
        },
        [vis](Vector3f w) { return vis.invert(w); });
}

TEST(WrongVariants, VisibleNormalsWithAbsoluteDotInsteadOfMask) {
    // Caught by the chi-square check's density integral (the tabulated check does
    // not apply: no coordinate of this warp depends on one input alone). The
    // grazing views are where back-facing normals carry mass.
    const auto chi2 = make_chi2_check();
    for (auto [alpha, theta_o] : {std::pair{1.0f, 85.0}, {0.3f, 85.0}, {1.0f, 60.0}}) {
        const CheckResult good = run_check(*chi2, *visible(alpha, theta_o, false));
        const CheckResult bad = run_check(*chi2, *visible(alpha, theta_o, true));
        EXPECT_EQ(good.verdict, Verdict::Pass) << alpha << " " << theta_o << ": " << good.message;
        EXPECT_EQ(bad.verdict, Verdict::Fail) << alpha << " " << theta_o;
        EXPECT_GT(*bad.figure("integral"), 1.0 + *bad.figure("integral_tolerance")) << alpha << " " << theta_o;
    }
}

}  // namespace
}  // namespace warpcheck
