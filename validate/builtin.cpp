// The warp families and checks that ship with warpcheck. Adding a family is one
// line here plus its register_*_cases function (see README, "Adding a warp").
#include "validate/checks/checks.h"
#include "validate/registry.h"

namespace warpcheck {

void register_builtin_cases(Registry& registry) {
    register_geometric_cases(registry);
    register_interval_cases(registry);
    register_linear_cases(registry);
    register_exponential_cases(registry);
    register_trowbridge_reitz_cases(registry);
    register_piecewise_constant_cases(registry);
}

void register_builtin_checks(Registry& registry) {
    registry.add_check(make_consistency_check());
    registry.add_check(make_roundtrip_check());
    registry.add_check(make_exhaustive_check());
    registry.add_check(make_binade_check());
    registry.add_check(make_exhaustive_roundtrip_check());
    registry.add_check(make_chi2_check());
    registry.add_check(make_tabulated_check());
    registry.add_check(make_unbinned_check());
}

}  // namespace warpcheck
