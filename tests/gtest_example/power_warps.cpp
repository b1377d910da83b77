// The renderer's registration: the same function feeds its validate program
// (warpcheck::main), its GoogleTest binary and its ctest tests.
#include "diffuse_bsdf.h"
#include "power_warp.h"

#include <validate/api/external.h>

namespace {

warpcheck::WarpCaseInfo power_case(const char* family, float n) {
    return {.family = family,
            .params = {{"n", n}},
            .description = "density (n+1) x^n on [0,1]",
            .domain = warpcheck::Domain::interval(0, 1)};
}

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    // n = 0.3f is named power[n=0.3]: a float parameter reads as the float it is.
    for (float n : {0.3f, 4.0f}) registry.add_case(warpcheck::make_warp_case(power_case("power", n), PowerWarp{n}));
    // Without an inverse: its round-trip checks do not apply (skipped tests, n/a rows).
    const PowerWarp cubic{3};
    registry.add_case(warpcheck::make_warp_case(
        power_case("power_no_inverse", 3),
            warpcheck::warp_of([cubic](float u) { return cubic.sample(u); })
                .with_pdf([cubic](float x) { return cubic.pdf(x); })));
    // A BSDF seen from two outgoing directions: the BSDF checks run on it.
    for (double theta : {0.0, 60.0})
        registry.add_case(warpcheck::make_bsdf_case({.family = "diffuse", .params = {{"theta_o", theta}}},
                                                    {.wo = warpcheck::bsdf_direction(theta)}, DiffuseBsdf{0.7f}));
#ifdef WITH_WRONG_WARP
    registry.add_case(warpcheck::make_warp_case(power_case("power_wrong", 2), WrongPowerWarp{}));
    registry.add_case(warpcheck::make_bsdf_case({.family = "diffuse_uniform_sampled", .params = {{"theta_o", 60}}},
                                                {.wo = warpcheck::bsdf_direction(60)},
                                                UniformlySampledDiffuse{DiffuseBsdf{0.7f}}));
#endif
}
