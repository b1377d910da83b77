// bsdf_reciprocity at f's float resolution (issue 22): rough glass seen at
// theta_o = 85 degrees transmits through facets whose interior cosine sits
// just inside the critical angle, where Fresnel's 1 - sin^2 t cancels and f
// moves by about 0.2% from one float of wi to the next. The rule measured f's
// resolution only 16 floats away, and on seed 1079 (warpcheck_fpr's run 80 of
// --first-seed 1000) one pair of 67,996, wi (-0.6049, -0.0175, -0.7961),
// differed by 1.4e-3 relative while its eight neighbours there all lay on one
// side of the jump: a false failure. The neighbours at 1, 4 and 16 floats see
// the jump; the correct case passes on 100 seeds, and a twin whose
// transmission from above is 0.5% too large still fails on every seed.
#include <gtest/gtest.h>

#include <string>

#include "sampling/bsdf_dielectric.h"
#include "sampling/float_bits.h"
#include "support/check_harness.h"
#include "validate/api/bsdf_case.h"
#include "validate/api/registry.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

/// Rough glass whose f from above the surface into it is `scale` times the
/// reciprocal value (sample and pdf unchanged).
struct ScaledTransmission {
    RoughDielectric glass;
    float scale = 1.0f;

    float eta() const { return glass.eta(); }
    Transport transport() const { return glass.transport(); }
    BsdfFlags flags() const { return glass.flags(); }
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        BsdfSample s = glass.sample(wo, uc, u);
        if (wo.z > 0.0f && s.wi.z < 0.0f) s.f *= scale;
        return s;
    }
    float f(Vector3f wo, Vector3f wi) const {
        return glass.f(wo, wi) * (wo.z > 0.0f && wi.z < 0.0f ? scale : 1.0f);
    }
    float pdf(Vector3f wo, Vector3f wi) const { return glass.pdf(wo, wi); }
};

/// Rough glass whose f carries 1% of noise from the float bits of its
/// arguments, different for (wo, wi) and (wi, wo): non-reciprocal by up to 2%
/// at every pair, and as noisy between neighbouring floats.
struct NoisyGlass {
    RoughDielectric glass;

    static float noise(Vector3f a, Vector3f b) {
        uint32_t h = 0x9e3779b9u;
        for (float v : {a.x, a.y, a.z, b.x, b.y, b.z}) h = (h ^ float_to_bits(v)) * 0x85ebca6bu, h ^= h >> 13;
        return 1.0f + 0.01f * (static_cast<float>(h >> 8) * 0x1p-23f - 1.0f);
    }
    float eta() const { return glass.eta(); }
    Transport transport() const { return glass.transport(); }
    BsdfFlags flags() const { return glass.flags(); }
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        BsdfSample s = glass.sample(wo, uc, u);
        s.f *= noise(wo, s.wi);
        return s;
    }
    float f(Vector3f wo, Vector3f wi) const { return glass.f(wo, wi) * noise(wo, wi); }
    float pdf(Vector3f wo, Vector3f wi) const { return glass.pdf(wo, wi); }
};

CheckResult reciprocity(const WarpCase& bsdf, uint64_t seed) {
    Registry registry;
    register_builtin_checks(registry);
    RunOptions options;
    options.seed = seed;
    options.threads = 2;
    options.check_time_budget = testing::kTestTimeBudget;
    return run_jobs({Job{&bsdf, registry.find_check("bsdf_reciprocity")}}, options).results.at(0);
}

double figure(const CheckResult& r, const std::string& name) {
    const auto f = r.figure(name);
    EXPECT_TRUE(f.has_value()) << name;
    return f.value_or(std::nan(""));
}

std::unique_ptr<WarpCase> glass(float scale) {
    // The built-in case's name and parameters, so the directions are the built-in's.
    return make_bsdf_case({.family = "rough_dielectric", .params = {{"alpha", 0.1}, {"eta", 1.5}, {"theta_o", 85}}},
                          {.wo = bsdf_direction(85)}, ScaledTransmission{RoughDielectric(TrowbridgeReitz(0.1f), 1.5f), scale});
}

TEST(BsdfReciprocity, RoughGlassAtGrazingPassesOnAHundredSeeds) {
    const auto correct = glass(1.0f);
    double excused = 0.0;
    for (uint64_t seed = 1000; seed < 1100; ++seed) {
        const CheckResult r = reciprocity(*correct, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << "seed " << seed << ": " << r.message;
        excused += figure(r, "excused_pairs");
        if (seed == 1079) {
            EXPECT_GE(figure(r, "excused_pairs"), 1.0) << "the pair that failed is excused, and counted";
        }
    }
    EXPECT_LT(excused, 100.0 * 1e-3 * 67'996) << "at most 1 pair in 1000 sits on f's rounding noise";
}

TEST(BsdfReciprocity, RoughGlassHalfAPercentOffStillFails) {
    const auto twin = glass(1.005f);
    for (uint64_t seed = 1000; seed < 1010; ++seed) {
        const CheckResult r = reciprocity(*twin, seed);
        EXPECT_EQ(r.verdict, Verdict::Fail) << "seed " << seed;
        EXPECT_GT(figure(r, "violations"), 1000.0) << "seed " << seed;
        // The message names the rule and the claims it was held to (issue 38).
        EXPECT_NE(r.message.find("rule: transmission with the claimed eta 1.5 and radiance transport: "
                                 "f(wo, wi) / eta(wo)^2 = f(wi, wo) / eta(wi)^2, scale s = "),
                  std::string::npos)
            << r.message;
    }
}

}  // namespace
}  // namespace warpcheck

namespace warpcheck {
namespace {

TEST(BsdfReciprocity, NoiseEverywhereIsNotExcusedAsFloatResolution) {
    const auto noisy = make_bsdf_case({.family = "rough_dielectric_noisy", .params = {{"theta_o", 85}}},
                                      {.wo = bsdf_direction(85)},
                                      NoisyGlass{RoughDielectric(TrowbridgeReitz(0.1f), 1.5f)});
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const CheckResult r = reciprocity(*noisy, seed);
        EXPECT_EQ(r.verdict, Verdict::Fail) << "seed " << seed;
        EXPECT_GT(figure(r, "grid_excused_pairs"), figure(r, "grid_excused_pairs_bound")) << "seed " << seed;
    }
    // The correct glass stays well inside the bound.
    const CheckResult r = reciprocity(*glass(1.0f), 1);
    EXPECT_LT(10.0 * figure(r, "grid_excused_pairs"), figure(r, "grid_excused_pairs_bound"));
}

}  // namespace
}  // namespace warpcheck

namespace warpcheck {
namespace {

// A lobe inside the critical angle's band as a whole: rough glass at alpha
// 0.005 and 0.001 seen at 89 degrees transmits every sample towards the
// direction whose reverse meets the surface at the critical angle, where
// f(wi, wo)'s 1 - F loses 1e-4 of itself to the cancellation in cos_t; the
// excused sampled pairs are counted, the bound is the grid's. Its twins of
// the same sharpness, 0.5% non-reciprocal and noisy by 1%, still fail.
std::unique_ptr<WarpCase> sharp_glass(float alpha, float scale) {
    return make_bsdf_case({.family = scale == 1.0f ? "sharp_glass" : "sharp_glass_scaled",
                           .params = {{"alpha", alpha}, {"scale", scale}, {"theta_o", 89}}},
                          {.wo = bsdf_direction(89)},
                          ScaledTransmission{RoughDielectric(TrowbridgeReitz(alpha), 1.5f), scale});
}

TEST(BsdfReciprocity, SharpGlassAtGrazingPassesOnSeveralSeeds) {
    for (float alpha : {0.005f, 0.001f}) {
        const auto correct = sharp_glass(alpha, 1.0f);
        for (uint64_t seed = 1; seed <= 5; ++seed) {
            const CheckResult r = reciprocity(*correct, seed);
            EXPECT_EQ(r.verdict, Verdict::Pass) << correct->name() << " seed " << seed << ": " << r.message;
            EXPECT_GT(figure(r, "excused_pairs"), 100.0) << "the lobe's pairs sit on f's rounding noise";
            EXPECT_LT(10.0 * figure(r, "grid_excused_pairs"), figure(r, "grid_excused_pairs_bound"));
        }
    }
}

// Dense glass (eta 2.4 and 4) at alpha 0.01 seen at 89 degrees: the reverse
// pair f(wi, wo) is seen from inside near the critical angle, where
// 1 - sin^2 t ~ 4e-4 and the inputs' length errors (~1e-8, which the
// neighbours' own rounding under-represents) move 1 - F by 2e-4. One pair of
// ~68,000 failed on seeds 2 and 3 (eta 2.4) and 3 (eta 4) before f's response
// to its inputs' lengths was part of its float resolution. Its twin,
// non-reciprocal by 0.2% across the interface, still fails.
std::unique_ptr<WarpCase> dense_glass(float eta, float scale) {
    return make_bsdf_case({.family = scale == 1.0f ? "dense_glass" : "dense_glass_scaled",
                           .params = {{"alpha", 0.01}, {"eta", eta}, {"scale", scale}, {"theta_o", 89}}},
                          {.wo = bsdf_direction(89)},
                          ScaledTransmission{RoughDielectric(TrowbridgeReitz(0.01f), eta), scale});
}

TEST(BsdfReciprocity, DenseGlassAtGrazingPassesOnSeveralSeeds) {
    for (float eta : {2.4f, 4.0f}) {
        const auto correct = dense_glass(eta, 1.0f);
        for (uint64_t seed = 1; seed <= 4; ++seed) {
            const CheckResult r = reciprocity(*correct, seed);
            EXPECT_EQ(r.verdict, Verdict::Pass) << correct->name() << " seed " << seed << ": " << r.message;
        }
        const auto twin = dense_glass(eta, 1.002f);
        for (uint64_t seed = 1; seed <= 2; ++seed) {
            const CheckResult r = reciprocity(*twin, seed);
            EXPECT_EQ(r.verdict, Verdict::Fail) << twin->name() << " seed " << seed;
            EXPECT_GT(figure(r, "violations"), 100.0) << twin->name() << " seed " << seed;
        }
    }
}

TEST(BsdfReciprocity, SharpGlassAtGrazingWrongTwinsFail) {
    for (float alpha : {0.005f, 0.001f}) {
        const auto twin = sharp_glass(alpha, 1.005f);
        const auto noisy = make_bsdf_case(
            {.family = "sharp_glass_noisy", .params = {{"alpha", alpha}, {"theta_o", 89}}}, {.wo = bsdf_direction(89)},
            NoisyGlass{RoughDielectric(TrowbridgeReitz(alpha), 1.5f)});
        for (uint64_t seed = 1; seed <= 3; ++seed) {
            const CheckResult r = reciprocity(*twin, seed);
            EXPECT_EQ(r.verdict, Verdict::Fail) << twin->name() << " seed " << seed;
            EXPECT_GT(figure(r, "violations"), 100.0) << twin->name() << " seed " << seed;
            const CheckResult n = reciprocity(*noisy, seed);
            EXPECT_EQ(n.verdict, Verdict::Fail) << noisy->name() << " seed " << seed;
        }
    }
}

}  // namespace
}  // namespace warpcheck
