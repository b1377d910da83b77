// A lobe narrower than the float directions that evaluate it (issue 38's
// extreme parameters): Henyey-Greenstein at g = 0.9999, whose peak, ~1e-4 rad
// wide, holds a density of ~1.6e7 that a float direction near the axis can
// only round to one of a few values of 1 - cos. Its float pdf's noise exceeds
// its own integral (bsdf_chi2's float_noise ~4), so:
//  - bsdf_chi2 cannot know any cell's expected count: the row is n/a and says
//    why (before, the largest residual failed it at p 1e-183), while at
//    g = 0.999 (noise 0.15 of the integral) the row still runs and passes;
//  - bsdf_albedo's energy rule is granted the same float-noise allowance as
//    its mean-weight rule (before, an energy albedo of 3.06 "created energy"
//    against a tolerance of 0.17 that left the noise out); where that
//    allowance reaches half the integral (g = 0.9999 and beyond), no albedo is
//    known and energy is judged from the sampled weights; the wrong twins, a
//    phase function that returns 2% too much at g = 0.99 (allowance 0.006),
//    1% too much at g = 0.99999 and 4 times too much at g = 0.9999, fail.
// And glass at the smallest roughness accepted (1e-4) seen from just inside
// the horizon (theta_o 91, total internal reflection), where the half vector
// wi + wo cancels to ~3.5e-6 across: the float wo's length error (1.5e-8)
// moves pdf(wo, .)'s lobe by ~0.4% of its width and its cos theta CDF by
// ~0.2%, which bsdf_unbinned used to blame on the sampler (7 of 8 seeds
// failed, p down to 3e-7; the sampler agrees with an independent
// double-precision one, KS p 0.46 over 4 10^6 samples). The response is now
// measured and carried into the test; a sampler whose roughness is 5% off at
// the same sharpness still fails.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "sampling/bsdf_conductor.h"
#include "sampling/bsdf_dielectric.h"
#include "sampling/bsdf_phase.h"
#include "support/check_harness.h"
#include "validate/api/bsdf_case.h"
#include "validate/api/registry.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

/// Henyey-Greenstein whose f (and so its samples' weights) is `gain` times
/// its pdf: energy created, the directions and pdf right.
struct GainingHg {
    HenyeyGreenstein hg;
    float gain = 1.0f;
    float p(Vector3f wo, Vector3f wi) const { return gain * hg.p(wo, wi); }
    float pdf(Vector3f wo, Vector3f wi) const { return hg.pdf(wo, wi); }
    BsdfSample sample(Vector3f wo, Point2f u) const {
        BsdfSample s = hg.sample(wo, u);
        s.f *= gain;
        return s;
    }
};

std::unique_ptr<WarpCase> sharp_hg(float g, float gain = 1.0f) {
    return make_phase_case({.family = gain == 1.0f ? "hg" : "hg_gaining", .params = {{"g", g}, {"gain", gain}}},
                           bsdf_direction(30), GainingHg{HenyeyGreenstein(g), gain});
}

/// 200,000 samples: the cells' quadrature of a lobe this sharp costs ~10 s a
/// row at validate's 10^6 (its accuracy target scales with 1 / sqrt(N)); the
/// float noise that decides these rows does not depend on N.
CheckResult sharp_run(const WarpCase& c, const std::string& check, uint64_t seed, uint64_t samples = 200'000) {
    Registry registry;
    register_builtin_checks(registry);
    RunOptions options;
    options.seed = seed;
    options.samples = samples;
    options.threads = 2;
    options.check_time_budget = testing::kTestTimeBudget;
    return run_jobs({Job{&c, registry.find_check(check)}}, options).results.at(0);
}

double sharp_figure(const CheckResult& r, const std::string& name) { return r.figure(name).value_or(std::nan("")); }

TEST(SharpLobe, HgAtPointNineNineNineNineIsNotApplicableToCellsOnSeveralSeeds) {
    const auto c = sharp_hg(0.9999f);
    for (uint64_t seed : {1, 2}) {
        const CheckResult r = sharp_run(*c, "bsdf_chi2", seed);
        EXPECT_EQ(r.verdict, Verdict::NotApplicable) << "seed " << seed << ": " << r.summary << " " << r.message;
        EXPECT_FALSE(r.p_value.has_value()) << "seed " << seed;
        EXPECT_GE(sharp_figure(r, "integral_tolerance"), sharp_figure(r, "pdf_integral")) << "seed " << seed;
        EXPECT_NE(r.summary.find("no cell can be tested"), std::string::npos) << r.summary;
    }
}

TEST(SharpLobe, HgAtPointNineNineNineIsStillTestedByCellsOnSeveralSeeds) {
    const auto c = sharp_hg(0.999f);
    for (uint64_t seed : {1, 2}) {
        const CheckResult r = sharp_run(*c, "bsdf_chi2", seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << "seed " << seed << ": " << r.summary << " " << r.message;
        EXPECT_LT(sharp_figure(r, "integral_tolerance"), sharp_figure(r, "pdf_integral")) << "seed " << seed;
    }
}

TEST(SharpLobe, HgEnergyAlbedoIsHeldWithinItsFloatNoiseOnSeveralSeeds) {
    for (float g : {0.99f, 0.999f, 0.9999f}) {
        const auto c = sharp_hg(g);
        for (uint64_t seed : {1, 2, 3}) {
            const CheckResult r = sharp_run(*c, "bsdf_albedo", seed);
            EXPECT_EQ(r.verdict, Verdict::Pass) << "g " << g << " seed " << seed << ": " << r.message;
            EXPECT_GE(sharp_figure(r, "energy_tolerance"), sharp_figure(r, "float_noise_allowance")) << "g " << g;
        }
    }
}

TEST(SharpLobe, HgCreatingEnergyFailsAtTheSameSharpness) {
    for (auto [g, gain] : {std::pair{0.99f, 1.02f}, std::pair{0.9999f, 4.0f}}) {
        const auto c = sharp_hg(g, gain);
        for (uint64_t seed : {1, 2, 3}) {
            const CheckResult r = sharp_run(*c, "bsdf_albedo", seed);
            EXPECT_EQ(r.verdict, Verdict::Fail) << "g " << g << " seed " << seed << ": " << r.message;
            const bool by_integral = r.message.find("the surface creates energy") != std::string::npos;
            const bool by_weights = r.summary.find("albedo unknown to the quadrature") != std::string::npos;
            EXPECT_TRUE(by_integral || by_weights) << r.summary << " | " << r.message;
        }
    }
}

/// At g = +-0.99999 the lobe (1e-5 rad) lies inside one float step of cos
/// near 1: f's integral came out 273 against a float-noise allowance of 232,
/// and the energy rule failed a correct phase function; at g = 0.9999 the
/// integral is 3.06 (allowance 2.28). No albedo is known there (the allowance
/// is at least half the integral): energy is judged from the sampled weights,
/// and a phase function 1% too bright still fails (4 times too bright at
/// g = 0.9999: HgCreatingEnergyFailsAtTheSameSharpness).
TEST(SharpLobe, HgBeyondFloatResolutionIsJudgedByItsWeightsOnSeveralSeeds) {
    for (float g : {0.9999f, 0.99999f, -0.99999f}) {
        const auto c = sharp_hg(g);
        for (uint64_t seed : {1, 2, 3}) {
            const CheckResult r = sharp_run(*c, "bsdf_albedo", seed);
            EXPECT_EQ(r.verdict, Verdict::Pass) << "g " << g << " seed " << seed << ": " << r.message;
            EXPECT_EQ(sharp_figure(r, "albedo_known"), 0.0) << "g " << g << ": " << r.summary;
            EXPECT_NE(r.message.find("energy is judged from the samples"), std::string::npos) << r.message;
        }
    }
    for (float g : {0.99f, 0.999f}) {  // the integral still knows the albedo
        const CheckResult r = sharp_run(*sharp_hg(g), "bsdf_albedo", 1);
        EXPECT_EQ(sharp_figure(r, "albedo_known"), 1.0) << "g " << g << ": " << r.summary;
    }
}

TEST(SharpLobe, HgBeyondFloatResolutionCreatingEnergyFailsByItsWeights) {
    const auto c = sharp_hg(0.99999f, 1.01f);
    for (uint64_t seed : {1, 2}) {
        const CheckResult r = sharp_run(*c, "bsdf_albedo", seed);
        EXPECT_EQ(r.verdict, Verdict::Fail) << "seed " << seed << ": " << r.message;
        EXPECT_EQ(sharp_figure(r, "albedo_known"), 0.0) << r.summary;
    }
}

/// f and pdf of `truth`, samples drawn by `sampler` (the same BSDF, or a twin
/// with a parameter off), weights `gain` times what they should be.
template <class B>
struct TwinSampled {
    B truth;
    B sampler;
    float gain = 1.0f;
    BsdfFlags flags() const { return truth.flags(); }
    float f(Vector3f wo, Vector3f wi) const { return truth.f(wo, wi); }
    float pdf(Vector3f wo, Vector3f wi) const { return truth.pdf(wo, wi); }
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        BsdfSample s = sampler.sample(wo, uc, u);
        if (s.pdf > 0.0f) {
            s.f = gain * truth.f(wo, s.wi);
            s.pdf = truth.pdf(wo, s.wi);
        }
        return s;
    }
};
struct TwinSampledGlass : TwinSampled<RoughDielectric> {
    float eta() const { return truth.eta(); }
};

/// Glass whose f and pdf have roughness 1e-4 and whose sampler draws visible
/// normals of roughness `sample_alpha` (1e-4: the built-in RoughDielectric).
std::unique_ptr<WarpCase> grazing_glass(float sample_alpha) {
    const RoughDielectric truth(TrowbridgeReitz(1e-4f), 1.5f);
    return make_bsdf_case({.family = sample_alpha == 1e-4f ? "rough_dielectric" : "rough_dielectric_wrong_alpha",
                           .params = {{"alpha", 1e-4}, {"sample_alpha", sample_alpha}, {"theta_o", 91}}},
                          {.wo = bsdf_direction(91)},
                          TwinSampledGlass{{truth, RoughDielectric(TrowbridgeReitz(sample_alpha), 1.5f)}});
}

/// 10^6 samples: the 0.2% shift is 2 / sqrt(N) there, invisible at 2 10^5.
/// Seeds 3 and 4 are two on which the row failed before (p 1.5e-4, 1e-4).
TEST(SharpLobe, GrazingGlassAtTheSmallestRoughnessPassesUnbinnedOnSeveralSeeds) {
    const auto c = grazing_glass(1e-4f);
    for (uint64_t seed : {3, 4}) {
        const CheckResult r = sharp_run(*c, "bsdf_unbinned", seed, 1'000'000);
        EXPECT_EQ(r.verdict, Verdict::Pass) << "seed " << seed << ": " << r.summary << " " << r.message;
        EXPECT_EQ(sharp_figure(r, "cos_theta_pdf_length_shift_carried"), 1.0) << "seed " << seed;
        EXPECT_GT(sharp_figure(r, "cos_theta_pdf_length_shift"), 1e-3) << "seed " << seed;
        EXPECT_LT(sharp_figure(r, "cos_theta_pdf_length_shift"), 5e-3) << "seed " << seed;
        EXPECT_NE(r.summary.find("the pdf's response to its directions"), std::string::npos) << r.summary;
        EXPECT_LT(sharp_figure(r, "power_tilt_eps_cos_theta"), 0.05) << "seed " << seed << ": " << r.summary;
    }
}

TEST(SharpLobe, GrazingGlassSampledWithItsRoughnessFivePercentOffFailsUnbinnedOnSeveralSeeds) {
    const auto c = grazing_glass(1.05e-4f);
    for (uint64_t seed : {3, 4}) {
        const CheckResult r = sharp_run(*c, "bsdf_unbinned", seed, 1'000'000);
        EXPECT_EQ(r.verdict, Verdict::Fail) << "seed " << seed << ": " << r.summary << " " << r.message;
        EXPECT_EQ(sharp_figure(r, "cos_theta_pdf_length_shift_carried"), 1.0) << "seed " << seed;
    }
}

/// wo = (0, 0, 1) is exactly unit length: nothing to carry, the same lobe
/// tested without the band.
TEST(SharpLobe, GlassSeenFromTheNormalCarriesNoLengthShift) {
    const auto c = make_bsdf_case({.family = "rough_dielectric", .params = {{"alpha", 1e-3}, {"theta_o", 0}}},
                                  {.wo = bsdf_direction(0)}, RoughDielectric(TrowbridgeReitz(1e-3f), 1.5f));
    const CheckResult r = sharp_run(*c, "bsdf_unbinned", 1);
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.summary << " " << r.message;
    EXPECT_EQ(sharp_figure(r, "cos_theta_pdf_length_shift"), 0.0) << r.summary;
    EXPECT_EQ(sharp_figure(r, "cos_theta_pdf_length_shift_carried"), 0.0) << r.summary;
}


/// Lobes thinner than the cubature's nodes (chi2::refine_by_pilot). Glass of
/// eta 1.001 and alpha 0.05 seen from theta_o 89 refracts nearly every draw
/// into a spot ~5e-5 rad across at the edge of a cell 0.045 tall, between
/// every node of the cell's rule and of its verifying split: the cells'
/// integral came out 0.99309 where the pdf integrates to 0.99396 (a double
/// precision sampler lands 0.99395), and the landing test failed the correct
/// sampler (p 3e-8, 4e-6). The pilot's cluster now places pieces around it.
std::unique_ptr<WarpCase> barely_refracting_glass(float sample_alpha) {
    const RoughDielectric truth(TrowbridgeReitz(0.05f), 1.001f);
    return make_bsdf_case({.family = sample_alpha == 0.05f ? "rough_dielectric" : "rough_dielectric_wrong_alpha",
                           .params = {{"alpha", 0.05}, {"eta", 1.001}, {"sample_alpha", sample_alpha}, {"theta_o", 89}}},
                          {.wo = bsdf_direction(89)},
                          TwinSampledGlass{{truth, RoughDielectric(TrowbridgeReitz(sample_alpha), 1.001f)}});
}

/// An anisotropic conductor of alpha 1e-3 x 1 seen from theta_o 89.5 at
/// phi_o 30: its lobe is a sheet ~1e-3 thick, crossing cells 3.7 rad wide in
/// phi, whose nodes stepped over it: bsdf_chi2 failed the correct sampler at
/// p 1e-172 (cells of 123 expected holding 608), and bsdf_albedo at t = 13
/// (the integral of f |cos| 0.2% short).
std::unique_ptr<WarpCase> sheet_conductor(float sample_ax, float gain = 1.0f) {
    const RoughConductor truth(TrowbridgeReitz(1e-3f, 1.0f), 0.2f, 3.0f);
    const bool right = sample_ax == 1e-3f && gain == 1.0f;
    return make_bsdf_case({.family = right ? "rough_conductor_aniso" : "rough_conductor_aniso_twin",
                           .params = {{"ax", 1e-3}, {"ay", 1}, {"sample_ax", sample_ax}, {"gain", gain},
                                      {"theta_o", 89.5}, {"phi_o", 30}}},
                          {.wo = bsdf_direction(89.5, 30)},
                          TwinSampled<RoughConductor>{truth, RoughConductor(TrowbridgeReitz(sample_ax, 1.0f), 0.2f, 3.0f),
                                                      gain});
}

TEST(ThinLobe, BarelyRefractingGlassPassesChiSquareOnSeveralSeeds) {
    const auto c = barely_refracting_glass(0.05f);
    for (uint64_t seed : {1, 2, 3}) {
        const CheckResult r = sharp_run(*c, "bsdf_chi2", seed, 1'000'000);
        EXPECT_EQ(r.verdict, Verdict::Pass) << "seed " << seed << ": " << r.summary << " " << r.message;
        // Seeds 1 and 2 failed before (landing p 3e-8, 4e-6): the pieces
        // restore mass there, and the landed share agrees with the integral.
        if (seed != 3) {
            EXPECT_GT(sharp_figure(r, "pilot_corrected_mass"), 1e-4) << "seed " << seed;
        }
        EXPECT_GT(sharp_figure(r, "landing_p_value"), 0.05) << "seed " << seed;
    }
}

TEST(ThinLobe, BarelyRefractingGlassSampledWithItsRoughnessFivePercentOffFailsOnSeveralSeeds) {
    const auto c = barely_refracting_glass(0.0525f);
    for (uint64_t seed : {1, 2, 3}) {
        const CheckResult r = sharp_run(*c, "bsdf_chi2", seed, 1'000'000);
        EXPECT_EQ(r.verdict, Verdict::Fail) << "seed " << seed << ": " << r.summary;
    }
}

TEST(ThinLobe, SheetConductorPassesChiSquareAndAlbedoOnSeveralSeeds) {
    const auto c = sheet_conductor(1e-3f);
    for (uint64_t seed : {1, 2, 3}) {
        const CheckResult chi2 = sharp_run(*c, "bsdf_chi2", seed, 1'000'000);
        EXPECT_EQ(chi2.verdict, Verdict::Pass) << "seed " << seed << ": " << chi2.summary << " " << chi2.message;
        EXPECT_GT(sharp_figure(chi2, "pilot_corrected_cells"), 0.0) << "seed " << seed;
        const CheckResult albedo = sharp_run(*c, "bsdf_albedo", seed, 1'000'000);
        EXPECT_EQ(albedo.verdict, Verdict::Pass) << "seed " << seed << ": " << albedo.summary << " " << albedo.message;
        EXPECT_GT(sharp_figure(albedo, "pilot_corrected_cells"), 0.0) << "seed " << seed;
    }
}

TEST(ThinLobe, SheetConductorTwinsFailOnSeveralSeeds) {
    const auto thicker = sheet_conductor(1.05e-3f);  // the sheet 5% thicker than f and pdf say
    const auto brighter = sheet_conductor(1e-3f, 1.01f);  // weights 1% high
    for (uint64_t seed : {1, 2, 3}) {
        const CheckResult chi2 = sharp_run(*thicker, "bsdf_chi2", seed, 1'000'000);
        EXPECT_EQ(chi2.verdict, Verdict::Fail) << "seed " << seed << ": " << chi2.summary;
        const CheckResult albedo = sharp_run(*brighter, "bsdf_albedo", seed, 1'000'000);
        EXPECT_EQ(albedo.verdict, Verdict::Fail) << "seed " << seed << ": " << albedo.summary;
    }
}

}  // namespace
}  // namespace warpcheck
