// Spectral BSDFs (make_spectral_bsdf_case, bsdf_spectral): every BSDF check
// per hero channel, each channel's rows its own tests in the run's Sidak
// family; the secondary channels held to f() and pdf() at the hero's samples
// within 2^-12 (twice that fails, half passes), terminated channels counted.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "sampling/bsdf_spectral.h"
#include "support/check_harness.h"
#include "validate/api/bsdf_case.h"
#include "validate/api/registry.h"
#include "validate/checks/bsdf/bsdf_checks.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

using testing::figure_of;

/// The RGB conductor with its blue value, as a secondary channel, scaled.
struct BlueScaled {
    RgbConductor base;
    float scale;
    BsdfFlags flags() const { return base.flags(); }
    SpectralSample<3> sample(Vector3f wo, float uc, Point2f u, int hero) const {
        SpectralSample<3> s = base.sample(wo, uc, u, hero);
        if (hero != 2) s.f[2] *= scale;
        return s;
    }
    std::array<float, 3> f(Vector3f wo, Vector3f wi) const { return base.f(wo, wi); }
    std::array<float, 3> pdf(Vector3f wo, Vector3f wi) const { return base.pdf(wo, wi); }
};

RgbConductor gold() { return RgbConductor(TrowbridgeReitz(0.3f), kGoldRgbEta, kGoldRgbK); }

// The built-in spectral families pass every BSDF check, each hero channel, on
// three seeds at a quarter of the default count.
TEST(BsdfSpectral, BuiltinsPassEveryCheckPerChannelOnSeveralSeeds) {
    Registry registry;
    register_builtin_cases(registry);
    register_builtin_checks(registry);
    RunOptions options;
    options.samples = 250'000;
    options.threads = 2;
    options.check_time_budget = testing::kTestTimeBudget;
    for (uint64_t seed : {1, 2, 3}) {
        options.seed = seed;
        const RunResult r =
            run_jobs(select_jobs(registry, {"rgb_conductor[", "dispersive_dielectric["}, {}, options), options);
        int spectral_rows = 0;
        for (const CheckResult& c : r.results) {
            EXPECT_TRUE(c.verdict == Verdict::Pass || c.verdict == Verdict::NotApplicable)
                << seed << " " << c.check_name << " " << c.case_name << ": " << c.summary << " " << c.message;
            spectral_rows += c.check_name == "bsdf_spectral" && c.verdict == Verdict::Pass;
        }
        EXPECT_EQ(spectral_rows, 4);  // three RGB heroes, the glass's first (its default grid)
    }
}

// The rule's edge, on the channel it does not sample with: blue 2^-11 high
// fails at every draw; 2^-13 high passes (within 2^-12).
TEST(BsdfSpectral, ASecondaryChannelTwiceTheToleranceOffFailsAndHalfOfItPasses) {
    const std::unique_ptr<Check> check = bsdf::make_bsdf_spectral_check();
    for (int hero : {0, 1}) {
        const auto off = make_spectral_bsdf_case({.family = "blue_off"}, {.wo = bsdf_direction(45)},
                                                 BlueScaled{gold(), 1.0f + 0x1p-11f}, hero);
        const CheckResult r = testing::run_check(*check, *off, 50'000);
        EXPECT_EQ(r.verdict, Verdict::Fail) << r.message;
        EXPECT_GT(figure_of(r, "f_mismatches"), 0.9 * figure_of(r, "compared"));
        const auto close = make_spectral_bsdf_case({.family = "blue_close"}, {.wo = bsdf_direction(45)},
                                                   BlueScaled{gold(), 1.0f + 0x1p-13f}, hero);
        EXPECT_EQ(testing::run_check(*check, *close, 50'000).verdict, Verdict::Pass) << hero;
    }
}

// Dispersion: every channel's pdf differs (the Fresnel choice and the half
// vector depend on eta), so a transmission terminates the secondaries
// (counted, not failed) and a reflection's secondary pdfs are each channel's
// own, compared.
TEST(BsdfSpectral, ADispersiveGlassTerminatesItsSecondariesAndReportsEachChannelsPdf) {
    const DispersiveDielectric<3> glass(TrowbridgeReitz(0.3f), {1.495f, 1.5f, 1.506f});
    const Vector3f wo = bsdf_direction(30);
    const Vector3f reflected{-wo.x, -wo.y, wo.z};
    const std::array<float, 3> p = glass.pdf(wo, reflected);
    EXPECT_NE(p[0], p[2]) << "the pdf depends on the wavelength";
    const auto hero0 = make_spectral_bsdf_case({.family = "glass"}, {.wo = wo}, glass, 0);
    const CheckResult r = testing::run_check(*bsdf::make_bsdf_spectral_check(), *hero0, 100'000);
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
    EXPECT_GT(figure_of(r, "terminated"), 50'000.0);
    EXPECT_EQ(as_bsdf(*hero0)->claims().eta, 1.495f) << "the hero's eta is the case's claim";
}

/// The RGB conductor with a fast path, sample_hero, that is not its sample()'s hero.
struct FastPathOff {
    RgbConductor base;
    BsdfFlags flags() const { return base.flags(); }
    BsdfSample sample_hero(Vector3f wo, float uc, Point2f u, int hero) const {
        BsdfSample s = base.sample_hero(wo, uc, u, hero);
        s.f *= 1.001f;
        return s;
    }
    SpectralSample<3> sample(Vector3f wo, float uc, Point2f u, int hero) const { return base.sample(wo, uc, u, hero); }
    std::array<float, 3> f(Vector3f wo, Vector3f wi) const { return base.f(wo, wi); }
    std::array<float, 3> pdf(Vector3f wo, Vector3f wi) const { return base.pdf(wo, wi); }
};

// The other checks see the hero through sample_hero where the object has
// one; bsdf_spectral holds it, bit for bit, to sample()'s hero channel.
TEST(BsdfSpectral, AFastPathThatIsNotTheSamplesHeroFails) {
    const auto off = make_spectral_bsdf_case({.family = "fast_path_off"}, {.wo = bsdf_direction(45)}, FastPathOff{gold()}, 0);
    const CheckResult r = testing::run_check(*bsdf::make_bsdf_spectral_check(), *off, 20'000);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_GT(figure_of(r, "hero_mismatches"), 10'000.0);
    const auto same = make_spectral_bsdf_case({.family = "fast_path"}, {.wo = bsdf_direction(45)}, gold(), 0);
    EXPECT_EQ(figure_of(testing::run_check(*bsdf::make_bsdf_spectral_check(), *same, 20'000), "hero_mismatches"), 0.0);
}

TEST(BsdfSpectral, AHeroThatIsNoChannelIsRefusedAndAPlainBsdfIsNotSpectral) {
    EXPECT_THROW(make_spectral_bsdf_case({.family = "x"}, {.wo = bsdf_direction(30)}, gold(), 3), std::invalid_argument);
    EXPECT_THROW(make_spectral_bsdf_case({.family = "x"}, {.wo = bsdf_direction(30)}, gold(), -1), std::invalid_argument);
    const auto channel = make_spectral_bsdf_case({.family = "x"}, {.wo = bsdf_direction(30)}, gold(), 1);
    ASSERT_NE(as_spectral(*channel), nullptr);
    EXPECT_EQ(as_spectral(*channel)->channels(), 3);
    EXPECT_EQ(as_spectral(*channel)->hero(), 1);
    const auto plain = make_bsdf_case({.family = "y"}, {.wo = bsdf_direction(30)}, RoughConductor(TrowbridgeReitz(0.3f), 0.2f, 3.0f));
    EXPECT_EQ(as_spectral(*plain), nullptr);
    EXPECT_FALSE(bsdf::make_bsdf_spectral_check()->applies_to(*plain));
}

}  // namespace
}  // namespace warpcheck
