// The renderer's GoogleTest binary: one test per (case, check) of its
// registration, and assertions on a warp object with its case info.
#include <gtest/gtest.h>

#include <validate/api/external.h>
#include <validate/gtest/warpcheck_gtest.h>

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

}  // namespace
