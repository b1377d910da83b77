// Cases whose names ctest discovery has to survive (run_discover.sh): an
// unbalanced '[', a ';', an escape sequence, a '*', a '+', two names that read
// alike once made plain for `ctest -R`, and a name too long for a file name.
// Each is the identity on [0,1); with DISCOVER_WRONG set, its inverse is
// halved, so that its round trip fails and writes evidence.
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include <validate/api/external.h>

namespace {

struct Identity {
    bool wrong = false;
    float sample(float u) const { return u; }
    float pdf(float x) const { return x >= 0 && x <= 1 ? 1.0f : 0.0f; }
    float invert(float x) const { return wrong ? 0.5f * x : x; }
};

}  // namespace

void warpcheck_register(warpcheck::Registry& registry) {
    const bool wrong = std::getenv("DISCOVER_WRONG") != nullptr;
    const auto add = [&](std::string family, std::vector<warpcheck::Parameter> params) {
        registry.add_case(warpcheck::make_warp_case({.family = std::move(family),
                                                     .params = std::move(params),
                                                     .description = "identity on [0,1), under an awkward name",
                                                     .domain = warpcheck::chi2::Domain::interval(0, 1)},
                                                    Identity{wrong}));
    };
    add("unbalanced[a", {{"b", 1}});
    add("semi;colon", {{"a", 1}});
    add("escape\x1b[31m", {{"a", 2}});
    add("star*name", {{"a", 1}});
    add("power", {{"n", 4}});
    add("power{n=4}", {});
    add("plus", {{"x", 1e7}});
    add(std::string(260, 'l') + "_long", {{"a", 1}});
}
