// EXPECT_BSDF_PASSES on a spectral BSDF's channel cases: each hero channel
// passes every BSDF check, bsdf_spectral among them; a channel's value 0.5%
// off fails the assertion seen from another channel, naming bsdf_spectral.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include "sampling/bsdf_spectral.h"
#include "validate/api/bsdf_case.h"
#include "validate/gtest/warpcheck_gtest.h"

namespace warpcheck {
namespace {

std::unique_ptr<WarpCase> gold_channel(int hero, SpectralFlaw flaw) {
    const WarpCaseInfo info{.family = flaw == SpectralFlaw::None ? "gtest_rgb_gold" : "gtest_rgb_gold_green_high",
                            .params = {{"hero", static_cast<double>(hero)}}};
    return make_spectral_bsdf_case(info, {.wo = bsdf_direction(40)},
                                   RgbConductor(TrowbridgeReitz(0.3f), kGoldRgbEta, kGoldRgbK, flaw), hero);
}

TEST(SpectralAssertion, EveryHeroChannelOfACorrectRgbBsdfPasses) {
    for (int hero : {0, 1, 2}) EXPECT_BSDF_PASSES(gold_channel(hero, SpectralFlaw::None));
}

TEST(SpectralAssertion, AGreenValueHalfAPercentHighFailsSeenFromRed) {
    EXPECT_NONFATAL_FAILURE(EXPECT_BSDF_PASSES(gold_channel(0, SpectralFlaw::GreenWeightHigh)), "bsdf_spectral");
}

}  // namespace
}  // namespace warpcheck
