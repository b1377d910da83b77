// The power of the BSDF checks at the default sample count (10^6), for the
// note: the smallest energy gain, weight error, lobe-probability error and
// error of the sampled lobe's shape each check detects in 90% of seeds,
// judged at the per-test level of a default `validate --all` run (Sidak over
// its statistical tests). Disabled by default (about six CPU minutes); run with
//   test_validate --gtest_also_run_disabled_tests --gtest_filter='BsdfPower*'
// It prints, per effect size, the share of 20 seeds on which each check failed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "chi2/multiple_testing.h"
#include "sampling/bsdf_conductor.h"
#include "sampling/bsdf_dielectric.h"
#include "sampling/bsdf_diffuse.h"
#include "support/bsdf_twins.h"
#include "validate/api/bsdf_case.h"
#include "validate/api/registry.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

constexpr int kSeeds = 20;

/// The per-test level of `validate --all` at the defaults.
double all_level() {
    Registry registry;
    register_builtin_cases(registry);
    register_builtin_checks(registry);
    int tests = 0;
    for (const Job& j : select_jobs(registry, {}, {}, RunOptions{}))
        if (j.check->statistical()) ++tests;
    std::printf("validate --all: %d statistical tests, per-test level %.3g\n", tests, chi2::sidak_level(0.01, tests));
    return chi2::sidak_level(0.01, tests);
}

/// Whether the check fails the case: a failure without a level, or a p-value
/// below `level` (the run's alpha over its one test is that level).
bool fails(const Check& check, const WarpCase& bsdf, uint64_t seed, double level) {
    RunOptions options;
    options.seed = seed;
    options.threads = 2;
    options.alpha = level;
    options.check_time_budget = 600.0;
    const RunResult run = run_jobs({Job{&bsdf, &check}}, options);
    return run.results.at(0).verdict == Verdict::Fail;
}

using Maker = std::function<std::unique_ptr<WarpCase>(double eps)>;

void scan(const char* effect, const Maker& make, const std::vector<double>& sizes,
          const std::vector<std::string>& checks, double level) {
    Registry registry;
    register_builtin_checks(registry);
    for (double eps : sizes) {
        const std::unique_ptr<WarpCase> bsdf = make(eps);
        std::printf("%s %.3g:", effect, eps);
        for (const std::string& name : checks) {
            int caught = 0;
            for (uint64_t seed = 1; seed <= kSeeds; ++seed) caught += fails(*registry.find_check(name), *bsdf, seed, level);
            std::printf("  %s %d/%d", name.c_str(), caught, kSeeds);
        }
        std::printf("\n");
    }
}

// Energy gain: a white Lambertian at theta_o = 85 scaled by 1 + eps (albedo
// 1 + eps), sampled and evaluated alike.
std::unique_ptr<WarpCase> energy_gain(double eps) {
    const auto gain = static_cast<float>(1.0 + eps);
    const Lambertian l(1.0f);
    return make_bsdf_case(
        {.family = "power_energy_gain"}, {.wo = bsdf_direction(85), .lobes = l.flags()},
        bsdf_of([l, gain](Vector3f wo, float uc, Point2f u) {
                    BsdfSample s = l.sample(wo, uc, u);
                    s.f *= gain;
                    return s;
                })
            .with_f([l, gain](Vector3f wo, Vector3f wi) { return gain * l.f(wo, wi); })
            .with_pdf([l](Vector3f wo, Vector3f wi) { return l.pdf(wo, wi); }));
}

// Weight error: a rough conductor (alpha 0.3, theta_o 60) whose sampled f is
// 1 + eps times f(): every weight off by eps relative.
std::unique_ptr<WarpCase> weight_error(double eps) {
    const RoughConductor c(TrowbridgeReitz(0.3f), 0.2f, 3.0f);
    const auto scale = static_cast<float>(1.0 + eps);
    return make_bsdf_case(
        {.family = "power_weight_error"}, {.wo = bsdf_direction(60), .lobes = c.flags()},
        bsdf_of([c, scale](Vector3f wo, float uc, Point2f u) {
                    BsdfSample s = c.sample(wo, uc, u);
                    s.f *= scale;
                    return s;
                })
            .with_f([c](Vector3f wo, Vector3f wi) { return c.f(wo, wi); })
            .with_pdf([c](Vector3f wo, Vector3f wi) { return c.pdf(wo, wi); }));
}

// Lobe-probability error: a smooth dielectric (theta_o 60, F = 0.089) that
// chooses reflection with probability F (1 + eps) while claiming F.
std::unique_ptr<WarpCase> lobe_error(double eps) {
    const SmoothDielectric d(1.5f);
    const auto scale = static_cast<float>(1.0 + eps);
    return make_bsdf_case(
        {.family = "power_lobe_error"}, {.wo = bsdf_direction(60), .lobes = d.flags(), .eta = 1.5f},
        bsdf_of([d, scale](Vector3f wo, float uc, Point2f u) { return d.sample(wo, uc / scale, u); })
            .with_f([d](Vector3f wo, Vector3f wi) { return d.f(wo, wi); })
            .with_pdf([d](Vector3f wo, Vector3f wi) { return d.pdf(wo, wi); }));
}

// Where the samples go, the weights agreeing (tests/support/bsdf_twins.h): a
// sharp conductor at 85 degrees sampled with alpha (1 + eps), and
// Henyey-Greenstein at g = 0.99 sampled with g + dg; bsdf_unbinned against
// bsdf_chi2's cells.
TEST(BsdfPower, DISABLED_SmallestShapeErrorsDetectedAtDefaultSamples) {
    const double level = all_level();
    scan(
        "roughness error", [](double eps) { return testing::conductor_wrong_roughness(0.05f, 85, eps); },
        {0.001, 0.0025, 0.005, 0.01}, {"bsdf_unbinned", "bsdf_chi2"}, level);
    scan(
        "g error", [](double dg) { return testing::henyey_greenstein_wrong_g(0.99f, static_cast<float>(dg)); },
        {2e-5, 5e-5, 1e-4, 2e-4}, {"bsdf_unbinned", "bsdf_chi2"}, level);
}

TEST(BsdfPower, DISABLED_SmallestEffectsDetectedAtDefaultSamples) {
    const double level = all_level();
    scan("energy gain", energy_gain, {1e-6, 3e-6, 1e-5, 1e-4}, {"bsdf_albedo"}, level);
    scan("weight error", weight_error, {1e-4, 2.5e-4, 1e-3, 3e-3}, {"bsdf_weight", "bsdf_albedo"}, level);
    scan("lobe probability error", lobe_error, {0.01, 0.015, 0.02, 0.03}, {"bsdf_delta", "bsdf_albedo"}, level);
}

}  // namespace
}  // namespace warpcheck
