// A registration that goes wrong in the ways GoogleTest cannot see coming,
// for awkward_registration_test (GoogleTest) and validate_awkward (warpcheck::main):
// - two cases whose names differ only in characters outside [A-Za-z0-9]
//   (power[n=2] and power_n_2 both read power_n_2 as a test name): each gets a
//   hash suffix, and both run;
// - a registration that fails at run time (a missing data file, say; here when
//   BREAK_REGISTRATION is set): the suite's one test, "registration", fails
//   with the reason, and so does a run whose filter then selects nothing; the
//   validate program says so under its own name.
#include <cstdlib>
#include <stdexcept>

#include <validate/api/external.h>

#include "power_warp.h"

namespace {

warpcheck::WarpCaseInfo power_info(const char* family, std::vector<warpcheck::Parameter> params) {
    return {.family = family,
            .params = std::move(params),
            .description = "density 3 x^2 on [0,1]",
            .domain = warpcheck::Domain::interval(0, 1)};
}

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    if (std::getenv("BREAK_REGISTRATION")) throw std::runtime_error("the lobe table could not be read");
    registry.add_case(warpcheck::make_warp_case(power_info("power", {{"n", 2}}), PowerWarp{2}));
    registry.add_case(warpcheck::make_warp_case(power_info("power_n_2", {}), PowerWarp{2}));
}

