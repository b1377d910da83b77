// Linear and bilinear warps (sampling/linear.h).
#include <utility>

#include "sampling/linear.h"
#include "validate/api/registry.h"

namespace warpcheck {
namespace {

void register_linear_cases(Registry& registry) {
    for (auto [a, b] : {std::pair{1.0, 3.0}, std::pair{0.0, 1.0}, std::pair{2.0, 0.0}}) {
        registry.add_case(make_warp_case({.family = "linear",
                                          .params = {{"a", a}, {"b", b}},
                                          .description = "density proportional to (1-x) a + x b on [0,1]",
                                          .domain = chi2::Domain::interval(0.0, 1.0)},
                                         Linear(static_cast<float>(a), static_cast<float>(b))));
    }
    registry.add_case(
        make_warp_case({.family = "bilinear",
                        .params = {{"w00", 1}, {"w10", 4}, {"w01", 0.5}, {"w11", 2}},
                        .description = "density proportional to the bilinear interpolation of corner weights",
                        .domain = chi2::Domain::unit_square()},
                       Bilinear(1.0f, 4.0f, 0.5f, 2.0f)));
}

WARPCHECK_BUILTIN_CASES(30, register_linear_cases);

}  // namespace
}  // namespace warpcheck
