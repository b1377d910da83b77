// The chi-square check on correct float warps that are hard for it (issue 22:
// a cancelling float pdf, a tiny cap's few float values of cos theta, a jump
// on the cells' diagonals, an area light's silhouette, a sliver of support
// between the quadrature's nodes) on several seeds, and on wrong twins of the
// same hardness, which must still fail. The warps are in
// tests/support/hard_float_warps.h.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>

#include "support/hard_float_warps.h"
#include "validate/checks/checks.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

using namespace testing::hard;

// Correct warps are judged at this level (the Sidak level of a full run is
// ~1e-4, so this is stricter than any run); wrong ones must fail it by far.
constexpr double kLevel = 1e-3;

CheckResult chi2_of(const WarpCase& warp, uint64_t seed, bool strict = false) {
    static const std::unique_ptr<Check> check = make_chi2_check();
    RunOptions options;
    options.samples = 1'000'000;
    options.threads = 2;
    options.seed = seed;
    options.strict = strict;
    options.check_time_budget = 600.0;
    options.alpha = kLevel;
    options.family_tests = 1;
    return run_jobs({Job{&warp, check.get()}}, options).results.at(0);
}

double float_figure(const CheckResult& r, const char* name) {
    return r.figure(name).value_or(std::numeric_limits<double>::quiet_NaN());
}

void expect_pass(const WarpCase& warp, uint64_t seed) {
    const CheckResult r = chi2_of(warp, seed);
    EXPECT_EQ(r.verdict, Verdict::Pass) << warp.name() << " seed " << seed << ": " << r.summary << " | " << r.message;
}

void expect_fail(const WarpCase& warp, const std::string& why, uint64_t seed = 1) {
    const CheckResult r = chi2_of(warp, seed);
    EXPECT_EQ(r.verdict, Verdict::Fail) << warp.name() << ": " << r.summary;
    EXPECT_NE(r.message.find(why), std::string::npos) << warp.name() << ": " << r.message;
}

const Vector3f kOblique = normalized({0.3f, -0.5f, 0.8f});

// Henyey-Greenstein's textbook float pdf integrates to 1 only to its float
// noise (1 + g^2 rounded before it cancels): it passes with the allowance,
// which the row names, on several seeds and directions.
TEST(Chi2Float, CancellingFloatPdfPassesWithItsAllowance) {
    for (float g : {0.9f, 0.99f})
        for (Vector3f forward : {Vector3f{0, 0, 1}, kOblique})
            for (uint64_t seed : {1, 2, 3}) expect_pass(*henyey_greenstein("hg", g, forward), seed);
    const CheckResult r = chi2_of(*henyey_greenstein("hg", 0.99f, {0, 0, 1}), 1);
    EXPECT_GT(std::abs(float_figure(r, "integral") - 1.0), 1e-5);  // the float pdf is off by far more than 2^-20
    EXPECT_LT(std::abs(float_figure(r, "integral") - 1.0), float_figure(r, "float_noise_allowance"));
    EXPECT_NE(r.summary.find("float rounding"), std::string::npos) << r.summary;
}

TEST(Chi2Float, CancellingFloatPdfFailsUnderStrict) {
    const CheckResult r = chi2_of(*henyey_greenstein("hg", 0.99f, {0, 0, 1}), 1, true);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_NE(r.message.find("not granted under --strict"), std::string::npos) << r.message;
}

// Wrong twins of the same hardness: a constant off by 1% at g = 0.99 (whose
// float pdf is itself off by up to 7e-4 over random directions, and granted
// up to ~3e-3), by 1e-3 at g = 0.9, by 1e-4 at g = 0.8, and a smooth density
// off by 5e-5.
TEST(Chi2Float, WrongConstantsStillFail) {
    expect_fail(*henyey_greenstein("hg_off", 0.99f, {0, 0, 1}, 1.01f), "integrates to");
    expect_fail(*henyey_greenstein("hg_off", 0.99f, kOblique, 1.01f), "integrates to");
    expect_fail(*henyey_greenstein("hg_off", 0.9f, kOblique, 1.001f), "integrates to");
    expect_fail(*henyey_greenstein("hg_off", 0.8f, {0, 0, 1}, 1.0001f), "integrates to");
    const auto sphere = make_warp_case(
        {.family = "sphere_off", .domain = chi2::Domain::sphere()},
        warp_of([](Point2f u) {
            const float z = 1.0f - 2.0f * u.x, r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * testing::hard::kPi * u.y;
            return Vector3f{r * std::cos(phi), r * std::sin(phi), z};
        })
            .with_pdf([](Vector3f) { return kInv4Pi * (1.0f + 5e-5f); }));
    expect_fail(*sphere, "integrates to");
}

std::unique_ptr<WarpCase> sun(double degrees, bool cap_domain, float azimuth_turn = 1.0f) {
    const auto c = static_cast<float>(std::cos(degrees * std::numbers::pi / 180.0));
    return make_warp_case({.family = cap_domain ? "sun_on_its_cap" : "sun_on_the_sphere",
                           .params = {{"degrees", degrees}},
                           .domain = cap_domain ? chi2::Domain::spherical_cap(c) : chi2::Domain::sphere()},
                          SunCone{c, 0.0f, azimuth_turn});
}

// A tiny cap has a few hundred float values of cos theta: on its own cap
// and on the whole sphere (a sliver of the uniform grid's top row: cells of
// equal probability at a pilot's quantiles there, integrated where it lies),
// it passes.
TEST(Chi2Float, TinySunPasses) {
    for (double degrees : {0.25, 0.5, 1.0})
        for (bool cap : {true, false})
            for (uint64_t seed : {1, 2}) expect_pass(*sun(degrees, cap), seed);
    const CheckResult r = chi2_of(*sun(0.25, false), 1);
    EXPECT_EQ(float_figure(r, "equal_probability_cells"), 1.0);
    // Its rim's float rounding (half a step of z, 0.3% of the cap) is carried
    // into the bands, and the row states what power is left (a tilt of about
    // 0.07: weak, and it says so).
    EXPECT_LT(float_figure(r, "power_tilt_eps"), 0.1);
    EXPECT_EQ(r.weak.empty(), float_figure(r, "power_tilt_eps") <= 0.05);
}

// The same sun with its azimuth 2% short still fails.
TEST(Chi2Float, TinySunWithAShortAzimuthFails) {
    for (bool cap : {true, false}) {
        const CheckResult r = chi2_of(*sun(0.25, cap, 0.98f), 1);
        EXPECT_EQ(r.verdict, Verdict::Fail) << r.summary;
    }
}

// A jump along x + y = 1 runs through the cells' corners, where symmetric
// nodes sit exactly on it: the verified bound covers the error, and the
// correct triangle passes; a density 1% off fails.
TEST(Chi2Float, JumpAlongTheCellDiagonalsPasses) {
    const auto triangle = make_warp_case({.family = "square_triangle", .domain = chi2::Domain::unit_square()},
                                         SquareTriangle{});
    for (uint64_t seed : {2, 3, 4, 5}) expect_pass(*triangle, seed);
    const CheckResult r = chi2_of(*triangle, 2);
    EXPECT_LE(std::abs(float_figure(r, "integral") - 1.0), float_figure(r, "integration_error") + 0x1p-20);
    EXPECT_GT(float_figure(r, "verification_mismatches"), 0.0);
    expect_fail(*make_warp_case({.family = "square_triangle_off", .domain = chi2::Domain::unit_square()},
                                SquareTriangle{1.98f}),
                "integrates to");
}

// An area light converted to solid angle: the pdf jumps to 0 at the
// silhouette. A pass, never an ERROR; the conversion without its cosine fails.
TEST(Chi2Float, AreaLightSilhouettePasses) {
    const auto light = make_warp_case({.family = "rectangle_light", .domain = chi2::Domain::hemisphere()},
                                      RectangleLight{0.7f, 0.4f});
    for (uint64_t seed : {1, 2, 3}) expect_pass(*light, seed);
    expect_fail(*make_warp_case({.family = "rectangle_light_no_cos", .domain = chi2::Domain::hemisphere()},
                                RectangleLight{0.7f, 0.4f, 0.0f, 2.0f}),
                "integrates to");
}

// A light thinner than a uniform cell, which the cubature's first nodes would
// miss: it passes; a twin whose samples spill beyond the light fails.
TEST(Chi2Float, SliverLightIsFoundAroundItsSamples) {
    const auto sliver = make_warp_case({.family = "sliver_light", .domain = chi2::Domain::hemisphere()},
                                       RectangleLight{0.5f, 0.002f});
    for (uint64_t seed : {1, 2}) expect_pass(*sliver, seed);
    // Found by cells of equal probability integrated where the pilot saw it,
    // or around the samples in cells whose nodes missed it.
    const CheckResult r = chi2_of(*sliver, 1);
    EXPECT_TRUE(float_figure(r, "reintegrated_cells") > 0.0 || float_figure(r, "equal_probability_cells") == 1.0);
    const auto spilling = make_warp_case({.family = "sliver_light_spilling", .domain = chi2::Domain::hemisphere()},
                                         RectangleLight{0.5f, 0.002f, 0.0025f});
    EXPECT_EQ(chi2_of(*spilling, 1).verdict, Verdict::Fail);
}

// A warp that returns NaN everywhere is a FAIL that says so, not an ERROR.
TEST(Chi2Float, NaNEverywhereFails) {
    const auto nan = make_warp_case({.family = "nan_everywhere", .domain = chi2::Domain::hemisphere()},
                                    warp_of([](Point2f) { return Vector3f{NAN, NAN, NAN}; })
                                        .with_pdf([](Vector3f) { return NAN; }));
    expect_fail(*nan, "every sample has NaN coordinates");
}

}  // namespace
}  // namespace warpcheck
