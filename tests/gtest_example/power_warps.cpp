// The renderer's registration: the same function feeds its validate program
// (warpcheck::main), its GoogleTest binary and its ctest tests.
#include "power_warp.h"

#include <validate/external.h>

namespace {

warpcheck::WarpCaseInfo power_case(const char* family, float n) {
    return {.family = family,
            .params = {{"n", n}},
            .description = "density (n+1) x^n on [0,1]",
            .input = warpcheck::InputKind::Uniform1D,
            .domain = warpcheck::chi2::Domain::interval(0, 1)};
}

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    for (float n : {1.0f, 4.0f}) registry.add_case(warpcheck::make_warp_case(power_case("power", n), PowerWarp{n}));
#ifdef WITH_WRONG_WARP
    registry.add_case(warpcheck::make_warp_case(power_case("power_wrong", 2), WrongPowerWarp{}));
#endif
}
