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
//    against a tolerance of 0.17 that left the noise out); its wrong twins,
//    a phase function that returns 2% too much at g = 0.99 (allowance 0.006)
//    and 4 times too much at g = 0.9999, still fail by that rule.
#include <gtest/gtest.h>

#include <memory>
#include <string>

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
CheckResult sharp_run(const WarpCase& c, const std::string& check, uint64_t seed) {
    Registry registry;
    register_builtin_checks(registry);
    RunOptions options;
    options.seed = seed;
    options.samples = 200'000;
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
            EXPECT_NE(r.message.find("the surface creates energy"), std::string::npos) << r.message;
        }
    }
}

}  // namespace
}  // namespace warpcheck
