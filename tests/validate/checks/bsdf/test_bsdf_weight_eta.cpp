// bsdf_weight's eta rule (issue 38): a continuous transmission must report the
// eta its case claims, eta(wi) / eta(wo), within 2^-20. The hard correct case
// is rough glass seen from inside, where that ratio is 1 / eta rounded to
// float (1 / 1.33 is not a float; the claim is divided in double) and at
// grazing angles, where few samples transmit; its wrong twin reports the
// material's eta from inside, with every direction, f, pdf and weight right,
// so that no other rule of the check sees it.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "sampling/bsdf_dielectric.h"
#include "support/check_harness.h"
#include "validate/api/bsdf_case.h"
#include "validate/api/registry.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

/// Rough glass whose transmissions from inside report the material's eta, not
/// 1 / eta, when `wrong` is set (the sample is otherwise the glass's own).
struct GlassReportingEta {
    RoughDielectric glass;
    bool wrong = false;

    float eta() const { return glass.eta(); }
    Transport transport() const { return glass.transport(); }
    BsdfFlags flags() const { return glass.flags(); }
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        BsdfSample s = glass.sample(wo, uc, u);
        if (wrong && wo.z < 0.0f && has(s.flags, BsdfFlags::Transmission)) s.eta = glass.eta();
        return s;
    }
    float f(Vector3f wo, Vector3f wi) const { return glass.f(wo, wi); }
    float pdf(Vector3f wo, Vector3f wi) const { return glass.pdf(wo, wi); }
};

std::unique_ptr<WarpCase> eta_glass(float alpha, float eta, double theta_o, bool wrong,
                                    Transport mode = Transport::Radiance) {
    return make_bsdf_case(
        {.family = wrong ? "glass_eta_from_inside_not_relative" : "glass",
         .params = {{"alpha", alpha}, {"eta", eta}, {"theta_o", theta_o}}},
        {.wo = bsdf_direction(theta_o)}, GlassReportingEta{RoughDielectric(TrowbridgeReitz(alpha), eta, mode), wrong});
}

CheckResult bsdf_weight_of(const WarpCase& bsdf, uint64_t seed) {
    Registry registry;
    register_builtin_checks(registry);
    RunOptions options;
    options.seed = seed;
    options.threads = 2;
    options.samples = 200'000;
    options.check_time_budget = testing::kTestTimeBudget;
    return run_jobs({Job{&bsdf, registry.find_check("bsdf_weight")}}, options).results.at(0);
}

double eta_figure(const CheckResult& r, const std::string& name) { return r.figure(name).value_or(std::nan("")); }

struct EtaSetting {
    float alpha, eta;
    double theta_o;
};
// From outside and inside, near normal and grazing, sharp and wide, at etas
// 1.5, 1.33 and 2.4 (none has a float inverse: from inside, the sample's
// 1 / eta is a float rounding of the claim's).
// (Sharper glass, whose edge inputs refract through facets on the horizon, is
// test_bsdf_weight_edges.cpp's.)
const std::vector<EtaSetting> kEtaSettings = {{0.1f, 1.5f, 30}, {0.1f, 1.5f, 150}, {0.5f, 1.33f, 95},
                                        {0.5f, 1.33f, 175}, {0.1f, 2.4f, 85},   {0.1f, 2.4f, 100}};

TEST(BsdfWeightEta, CorrectGlassFromBothSidesPassesOnSeveralSeeds) {
    for (const EtaSetting& s : kEtaSettings)
        for (Transport mode : {Transport::Radiance, Transport::Importance})
            for (uint64_t seed : {1, 2, 3}) {
                const auto bsdf = eta_glass(s.alpha, s.eta, s.theta_o, false, mode);
                const CheckResult r = bsdf_weight_of(*bsdf, seed);
                EXPECT_EQ(r.verdict, Verdict::Pass) << bsdf->name() << " seed " << seed << ": " << r.message;
                EXPECT_EQ(eta_figure(r, "wrong_eta"), 0.0) << bsdf->name();
                EXPECT_EQ(eta_figure(r, "eta_tolerance"), 0x1p-20);
            }
}

TEST(BsdfWeightEta, GlassReportingItsEtaFromInsideFailsOnEverySeedAndOnlyByThatRule) {
    for (const EtaSetting& s : kEtaSettings) {
        if (s.theta_o < 90) continue;  // the twin is wrong only from inside
        for (uint64_t seed : {1, 2, 3}) {
            const auto bsdf = eta_glass(s.alpha, s.eta, s.theta_o, true);
            const CheckResult r = bsdf_weight_of(*bsdf, seed);
            EXPECT_EQ(r.verdict, Verdict::Fail) << bsdf->name() << " seed " << seed;
            EXPECT_GT(eta_figure(r, "wrong_eta"), 0.0) << bsdf->name();
            for (const char* other : {"not_unit", "wrong_side", "zero_pdf", "zero_f", "weight_mismatches", "bad_delta"})
                EXPECT_EQ(eta_figure(r, other), 0.0) << bsdf->name() << ": " << other;
            EXPECT_NE(r.message.find("eta is not the claimed eta(wi) / eta(wo)"), std::string::npos) << r.message;
        }
    }
}

}  // namespace
}  // namespace warpcheck
