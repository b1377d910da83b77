// The renderer's GoogleTest binary: one test per (case, check) of its
// registration, and assertions on a warp object with its case info and on a
// BSDF object at one outgoing direction.
#include <gtest/gtest.h>

#include <validate/api/external.h>
#include <validate/gtest/warpcheck_gtest.h>

#include "diffuse_bsdf.h"
#include "power_warp.h"

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

}  // namespace
