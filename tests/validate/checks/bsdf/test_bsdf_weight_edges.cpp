// bsdf_weight's float-resolution rule at the edge of a BSDF's support (issue
// 38). The hard correct case is sharp rough glass: the edge inputs u.x = 2^-k
// sample microfacet normals on the horizon (wm.z ~ 4e-8), whose refraction
// leaves wi where the half vector recomputed from the rounded wi has its z of
// either sign, so f() and pdf() at wi are 0 while the float neighbours of wi
// agree with the sample's weight to a few float roundings. Those samples are
// excused and counted, and only edge inputs may need it. Its wrong twins are
// wrong exactly there (a weight off by 0.5%, a sliver 2^-12 beyond the edge),
// and a BSDF whose f() and pdf() vanish on 1/256 of the directions, each
// sample of which the excuse would take, fails by the excuse's bound.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <memory>
#include <string>

#include "sampling/bsdf_dielectric.h"
#include "sampling/bsdf_diffuse.h"
#include "support/check_harness.h"
#include "validate/api/bsdf_case.h"
#include "validate/checks/bsdf/bsdf_checks.h"

namespace warpcheck {
namespace {

/// How rough glass is wrong at the microfacets on the horizon (wm.z below
/// 2^-10), the samples the float-resolution rule looks at.
enum class HorizonFlaw { None, WeightOff, BeyondEdge };

struct GlassWithHorizonFlaw {
    RoughDielectric glass;
    TrowbridgeReitz distribution;
    HorizonFlaw flaw = HorizonFlaw::None;

    float eta() const { return glass.eta(); }
    Transport transport() const { return glass.transport(); }
    BsdfFlags flags() const { return glass.flags(); }
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        BsdfSample s = glass.sample(wo, uc, u);
        if (flaw == HorizonFlaw::None || s.pdf == 0.0f || !has(s.flags, BsdfFlags::Transmission)) return s;
        if (!(distribution.visible_normals(wo).sample(u).z < 0x1p-10f)) return s;
        if (flaw == HorizonFlaw::WeightOff) {
            s.f *= 1.005f;
        } else {
            // Up by 2^-12 and renormalised: the half vector eta wi + wo, which
            // points below the horizon for a refraction through an upward facet
            // (f() and pdf() turn it up), rises above it, far beyond wi's float
            // neighbours: f() and pdf() there take it for the wrong facet.
            Vector3f w{s.wi.x, s.wi.y, s.wi.z + 0x1p-12f};
            s.wi = normalize(w);
        }
        return s;
    }
    float f(Vector3f wo, Vector3f wi) const { return glass.f(wo, wi); }
    float pdf(Vector3f wo, Vector3f wi) const { return glass.pdf(wo, wi); }
};

std::unique_ptr<WarpCase> edge_glass(float alpha, double theta_o, HorizonFlaw flaw) {
    const char* family = flaw == HorizonFlaw::None        ? "glass"
                         : flaw == HorizonFlaw::WeightOff ? "glass_horizon_weight_off"
                                                          : "glass_horizon_beyond_edge";
    const TrowbridgeReitz tr(alpha);
    return make_bsdf_case({.family = family, .params = {{"alpha", alpha}, {"theta_o", theta_o}}},
                          {.wo = bsdf_direction(theta_o)}, GlassWithHorizonFlaw{RoughDielectric(tr, 1.5f), tr, flaw});
}

/// A Lambertian surface whose f() and pdf() are 0 at the directions whose
/// wi.x has its low 8 bits clear (1/256 of them, scattered over the whole
/// hemisphere): nearly every such sample's neighbours agree with its weight
/// (not near wi.x = +-1, where the neighbours' x rounds to the same float).
struct LambertianWithHoles {
    Lambertian lambert{0.5f};
    static bool hole(Vector3f wi) { return (std::bit_cast<uint32_t>(wi.x) & 0xffu) == 0; }
    BsdfFlags flags() const { return lambert.flags(); }
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const { return lambert.sample(wo, uc, u); }
    float f(Vector3f wo, Vector3f wi) const { return hole(wi) ? 0.0f : lambert.f(wo, wi); }
    float pdf(Vector3f wo, Vector3f wi) const { return hole(wi) ? 0.0f : lambert.pdf(wo, wi); }
};

CheckResult edges_weight_of(const WarpCase& bsdf, uint64_t seed) {
    static const std::unique_ptr<Check> check = bsdf::make_bsdf_weight_check();
    return testing::run_check(*check, bsdf, 200'000, 2, seed);
}

double edges_figure(const CheckResult& r, const std::string& name) { return r.figure(name).value_or(std::nan("")); }

struct EdgeSetting {
    float alpha;
    double theta_o;
};
// Sharp and very sharp, near normal and grazing, from outside and inside.
constexpr EdgeSetting kEdgeSettings[] = {{0.05f, 30}, {0.05f, 85}, {0.02f, 30}, {0.05f, 150}};

TEST(BsdfWeightEdges, SharpGlassPassesOnSeveralSeedsWithItsHorizonSamplesExcused) {
    for (const EdgeSetting& s : kEdgeSettings)
        for (uint64_t seed : {1, 2, 3, 4, 5}) {
            const auto bsdf = edge_glass(s.alpha, s.theta_o, HorizonFlaw::None);
            const CheckResult r = edges_weight_of(*bsdf, seed);
            EXPECT_EQ(r.verdict, Verdict::Pass) << bsdf->name() << " seed " << seed << ": " << r.message;
            if (s.theta_o < 90) {  // from outside, the horizon facets refract: the rule is exercised
                EXPECT_GT(edges_figure(r, "excused_outside_support"), 0.0) << bsdf->name();
            }
            EXPECT_LE(edges_figure(r, "excused_random"), edges_figure(r, "excused_random_limit")) << bsdf->name();
            EXPECT_EQ(edges_figure(r, "zero_pdf"), 0.0) << bsdf->name();
        }
}

TEST(BsdfWeightEdges, GlassWrongAtItsHorizonFacetsFailsOnSeveralSeeds) {
    for (HorizonFlaw flaw : {HorizonFlaw::WeightOff, HorizonFlaw::BeyondEdge})
        for (const EdgeSetting& s : kEdgeSettings) {
            if (s.theta_o > 90) continue;  // from inside no horizon facet refracts
            for (uint64_t seed : {1, 2, 3}) {
                const auto bsdf = edge_glass(s.alpha, s.theta_o, flaw);
                const CheckResult r = edges_weight_of(*bsdf, seed);
                EXPECT_EQ(r.verdict, Verdict::Fail) << bsdf->name() << " seed " << seed;
                EXPECT_GT(edges_figure(r, "zero_pdf"), 0.0) << bsdf->name() << " seed " << seed;
                EXPECT_EQ(edges_figure(r, "excused_outside_support"), 0.0) << bsdf->name() << " seed " << seed;
            }
        }
}

TEST(BsdfWeightEdges, DiffuseWithHolesInItsPdfFailsByTheExcuseBound) {
    for (uint64_t seed : {1, 2, 3}) {
        const auto bsdf = make_bsdf_case({.family = "lambertian_with_holes", .params = {}},
                                         {.wo = bsdf_direction(30)}, LambertianWithHoles{});
        const CheckResult r = edges_weight_of(*bsdf, seed);
        EXPECT_EQ(r.verdict, Verdict::Fail) << "seed " << seed;
        EXPECT_GT(edges_figure(r, "excused_random"), edges_figure(r, "excused_random_limit")) << "seed " << seed;
        EXPECT_NE(r.message.find("more random inputs' samples at float resolution"), std::string::npos) << r.message;
    }
}

}  // namespace
}  // namespace warpcheck

namespace warpcheck {
namespace {

/// A Lambertian of reflectance R whose samples or f() are wrong on wi.x > 0:
/// None is a black surface when R = 0 (every sample's f is 0, as is f()).
enum class ZeroFlaw { None, SampleClaimsWhereFIsZero, SampleZeroWhereFIsNot };
struct DiffuseZeroWeights {
    Lambertian lambert;
    ZeroFlaw flaw = ZeroFlaw::None;
    BsdfFlags flags() const { return lambert.flags(); }
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        BsdfSample s = lambert.sample(wo, uc, u);
        if (flaw == ZeroFlaw::SampleClaimsWhereFIsZero && s.pdf > 0.0f) s.f = 0.5f / 3.14159265f;
        if (flaw == ZeroFlaw::SampleZeroWhereFIsNot && s.wi.x > 0.0f) s.f = 0.0f;
        return s;
    }
    float f(Vector3f wo, Vector3f wi) const { return lambert.f(wo, wi); }
    float pdf(Vector3f wo, Vector3f wi) const { return lambert.pdf(wo, wi); }
};

std::unique_ptr<WarpCase> zero_weight_diffuse(float R, ZeroFlaw flaw) {
    return make_bsdf_case({.family = "zero_weight_diffuse", .params = {{"R", R}, {"flaw", static_cast<double>(flaw)}}},
                          {.wo = bsdf_direction(30)}, DiffuseZeroWeights{Lambertian(R), flaw});
}

TEST(BsdfWeightZero, ABlackSurfacesSamplesOfWeightZeroPassAndAreCountedOnSeveralSeeds) {
    for (uint64_t seed : {1, 2, 3}) {
        const CheckResult r = edges_weight_of(*zero_weight_diffuse(0.0f, ZeroFlaw::None), seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
        EXPECT_EQ(edges_figure(r, "zero_weight_samples"), edges_figure(r, "sampled")) << r.message;
        EXPECT_GT(edges_figure(r, "sampled"), 100000.0);
    }
}

TEST(BsdfWeightZero, ASampleClaimingFWhereFIsZeroStillFails) {
    // The same black surface, its sampler claiming R / pi with R = 0.5: f() is 0 at every sample.
    const CheckResult r = edges_weight_of(*zero_weight_diffuse(0.0f, ZeroFlaw::SampleClaimsWhereFIsZero), 1);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_NE(r.message.find("lands where f(wo, wi) is 0"), std::string::npos) << r.message;
}

TEST(BsdfWeightZero, ASampleOfWeightZeroWhereFIsPositiveFails) {
    const CheckResult r = edges_weight_of(*zero_weight_diffuse(0.5f, ZeroFlaw::SampleZeroWhereFIsNot), 1);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_NE(r.message.find("the weight differs"), std::string::npos) << r.message;
    EXPECT_EQ(edges_figure(r, "zero_weight_samples"), 0.0);
}

}  // namespace
}  // namespace warpcheck
