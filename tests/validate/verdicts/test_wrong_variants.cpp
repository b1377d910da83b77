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
#include "support/wrong_variants.h"
#include "validate/checks/checks.h"

namespace warpcheck {
namespace {

using testing::run_check;
using testing::tr_normals;
using testing::trimmed;
using testing::visible;

// --- Trowbridge-Reitz with alpha in place of alpha^2 ---------------------------

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
