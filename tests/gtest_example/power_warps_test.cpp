// The renderer's GoogleTest binary: one test per (case, check) of its
// registration, and assertions on a warp object with its case info, on a
// BSDF object at one outgoing direction, on a light seen from one point, and
// on the MIS of the BSDF and the light there.
#include <gtest/gtest.h>

#include <validate/api/external.h>
#include <validate/gtest/warpcheck_gtest.h>

#include "diffuse_bsdf.h"
#include "power_warp.h"
#include "sphere_light.h"

WARPCHECK_TEST_SUITE(PowerWarps, warpcheck_register);

namespace {

warpcheck::WarpCaseInfo lobe(float n) {
    return {.family = "power_lobe",
            .params = {{"n", n}},
            .description = "density (n+1) x^n on [0,1]",
            .domain = warpcheck::Domain::interval(0, 1)};
}

TEST(PowerWarp, CubicLobe) { EXPECT_WARP_PASSES(warpcheck::make_warp_case(lobe(3), PowerWarp{3})); }

#ifdef WITH_WRONG_WARP
TEST(PowerWarp, WrongLobe) { EXPECT_WARP_PASSES(warpcheck::make_warp_case(lobe(2), WrongPowerWarp{})); }
#endif

// A BSDF at one outgoing direction, with every BSDF check that applies.
warpcheck::WarpCaseInfo grazing(const char* family) { return {.family = family, .params = {{"theta_o", 85}}}; }

TEST(DiffuseBsdf, Grazing) {
    const auto diffuse =
        warpcheck::make_bsdf_case(grazing("diffuse_grazing"), {.wo = warpcheck::bsdf_direction(85)}, DiffuseBsdf{0.7f});
    EXPECT_BSDF_PASSES(diffuse);
}

#ifdef WITH_WRONG_WARP
TEST(DiffuseBsdf, UniformlySampled) {
    const auto wrong = warpcheck::make_bsdf_case(grazing("diffuse_uniform_grazing"), {.wo = warpcheck::bsdf_direction(85)},
                                                 UniformlySampledDiffuse{DiffuseBsdf{0.7f}});
    EXPECT_BSDF_PASSES(wrong);
}
#endif

// A sphere light seen from a point on a surface (normal +z), with every check
// that applies to a light; then the diffuse BSDF and that light combined by
// the power heuristic, as direct lighting combines them.
constexpr warpcheck::LightClaims kOnSurface{.ref = {0, 0, 0}, .normal = {0, 0, 1}};
const SphereLight kSphere{{2.0f, 0.0f, 3.4641016f}, 1.0f, 2.0f};

TEST(SphereLight, SeenFromASurface) {
    EXPECT_LIGHT_PASSES(warpcheck::make_light_case({.family = "sphere_light"}, kOnSurface, kSphere));
}

std::unique_ptr<warpcheck::WarpCase> direct_lighting(const char* family, warpcheck::MisClaims claims) {
    return warpcheck::make_mis_case(
        {.family = family}, std::move(claims),
        warpcheck::make_bsdf_case({.family = "diffuse"}, {.wo = warpcheck::bsdf_direction(40, 180)}, DiffuseBsdf{0.7f}),
        warpcheck::make_light_case({.family = "sphere_light"}, kOnSurface, kSphere));
}

TEST(DirectLighting, DiffuseUnderASphere) { EXPECT_MIS_PASSES(direct_lighting("direct", {})); }

#ifdef WITH_WRONG_WARP
TEST(DirectLighting, AreaPdfInTheSum) {
    warpcheck::MisClaims claims;
    claims.pdfs.lights.push_back([](warpcheck::Vector3f ref, warpcheck::Vector3f wi) { return kSphere.pdf_per_area(ref, wi); });
    EXPECT_MIS_PASSES(direct_lighting("direct_area_pdf", std::move(claims)));
}
#endif

}  // namespace
