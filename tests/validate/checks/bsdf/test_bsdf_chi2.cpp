// bsdf_chi2 where the cubature's first nodes see nothing: a continuous lobe
// thinner than the nodes' spacing (a band of heights a thirtieth of a row
// high) is integrated again around the samples that land in the cells it was
// missed in, as the chi2 check does, and passes; a twin
// whose samples spill beyond its pdf fails; and a sample where the pdf is 0
// is a FAIL that no ERROR (too few samples for any degree of freedom) hides.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "sampling/bsdf.h"
#include "validate/api/bsdf_case.h"
#include "validate/checks/bsdf/bsdf_checks.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

/// A phase function that scatters uniformly (in solid angle) into a thin band
/// of heights z in [z0, z1] of the sphere, whatever wo: a sliver of support
/// in one row of the default cells (32 azimuths by 64 heights), z sampled as
/// the coordinate it is. The band [-0.733, -0.7325] lies between two nodes of
/// the 15-point rule in its row ([-0.75, -0.71875]: its middle -0.734375, and
/// 0.2077 of its half-height above, -0.73113), so the cubature sees nothing
/// in any of the row's 32 cells. `below` widens the sampled band downwards,
/// beyond the pdf's, into the row below, where the pdf is 0 everywhere.
struct ThinBand {
    float z0 = -0.733f, z1 = -0.7325f;
    float below = 0.0f;

    float density() const { return 1.0f / (kTwoPi * (z1 - z0)); }
    float p(Vector3f, Vector3f wi) const { return wi.z >= z0 && wi.z <= z1 ? density() : 0.0f; }
    float pdf(Vector3f wo, Vector3f wi) const { return p(wo, wi); }
    BsdfSample sample(Vector3f, Point2f u) const {
        const float z = z1 - u.x * (z1 - z0 + below), r = safe_sqrt(1.0f - z * z);
        const SinCos phi = sin_cos(kTwoPi * u.y);
        return {{r * phi.cos, r * phi.sin, z}, density(), density(), BsdfFlags::Continuous};
    }
};

std::unique_ptr<WarpCase> band_case(const std::string& family, ThinBand band) {
    return make_phase_case({.family = family, .params = {{"theta_o", 30}}}, bsdf_direction(30), band);
}

CheckResult bsdf_chi2_of(const WarpCase& bsdf, uint64_t seed, uint64_t samples = 1'000'000) {
    static const std::unique_ptr<Check> check = bsdf::make_bsdf_chi2_check();
    RunOptions options;
    options.seed = seed;
    options.samples = samples;
    options.threads = 2;
    options.check_time_budget = 600.0;
    options.family_tests = 1;
    return run_jobs({Job{&bsdf, check.get()}}, options).results.at(0);
}

double figure(const CheckResult& r, const char* name) { return r.figure(name).value_or(std::nan("")); }

TEST(BsdfChi2ZeroCells, NarrowLobeIsIntegratedAroundItsSamples) {
    const auto band = band_case("thin_band", ThinBand{});
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const CheckResult r = bsdf_chi2_of(*band, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << "seed " << seed << ": " << r.summary << " | " << r.message;
        // Found either by cells of equal probability integrated where the
        // pilot saw the band, or around the samples in the cells it missed.
        EXPECT_TRUE(figure(r, "reintegrated_cells") > 0.0 || figure(r, "equal_probability_cells") == 1.0)
            << "seed " << seed;
        EXPECT_GE(figure(r, "dof"), 1.0) << "seed " << seed;
    }
}

TEST(BsdfChi2ZeroCells, SamplesBeyondThePdfFail) {
    // Sampled 0.03 further down: most samples land in the row below, where
    // the pdf is 0 at every one of them.
    const CheckResult r = bsdf_chi2_of(*band_case("thin_band_spilling", ThinBand{.below = 0.03f}), 1);
    EXPECT_EQ(r.verdict, Verdict::Fail) << r.summary;
    EXPECT_GT(figure(r, "zero_expected_hits"), 0.0) << r.message;
}

TEST(BsdfChi2ZeroCells, ZeroPdfHitsFailEvenWhereNoStatisticCanBeFormed) {
    // The same with so few samples that no degree of freedom remains: the
    // hits decide, not the error.
    const CheckResult r = bsdf_chi2_of(*band_case("thin_band_spilling", ThinBand{.below = 0.03f}), 1, 5);
    EXPECT_EQ(r.verdict, Verdict::Fail) << r.summary << " | " << r.message;
    EXPECT_NE(r.message.find("density integrates to zero"), std::string::npos) << r.message;
    EXPECT_EQ(figure(r, "dof"), 0.0) << "a statistic was formed after all: " << r.summary;
}

}  // namespace
}  // namespace warpcheck
