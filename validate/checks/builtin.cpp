// The warp families and checks that ship with warpcheck. Families register
// themselves from their files in validate/cases (WARPCHECK_BUILTIN_CASES), so
// adding one edits no list here (see README, "Adding a warp").
#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

#include "validate/checks/bsdf/bsdf_checks.h"
#include "validate/checks/checks.h"
#include "validate/checks/light/light_checks.h"
#include "validate/checks/repeatability/repeatability_check.h"
#include "validate/api/registry.h"

namespace warpcheck {
namespace {

struct BuiltinFamily {
    int rank;
    std::string name;
    detail::RegisterCasesFn fn;
};

// A function-local static: the case files' static initialisers may run before
// any namespace-scope object of this file is constructed.
std::vector<BuiltinFamily>& builtin_families() {
    static std::vector<BuiltinFamily> families;
    return families;
}

}  // namespace

bool detail::add_builtin_cases(int rank, const char* name, RegisterCasesFn fn) {
    builtin_families().push_back({rank, name, fn});
    return true;
}

void register_builtin_cases(Registry& registry) {
    // Static initialisation order across files is unspecified: sort.
    std::vector<BuiltinFamily> families = builtin_families();
    std::sort(families.begin(), families.end(), [](const BuiltinFamily& l, const BuiltinFamily& r) {
        return std::tie(l.rank, l.name) < std::tie(r.rank, r.name);
    });
    for (const BuiltinFamily& family : families) family.fn(registry);
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
    registry.add_check(make_sample_pdf_check());
    registry.add_check(make_weight_check());
    registry.add_check(make_weight_mean_check());
    registry.add_check(make_inverse_pdf_mean_check());
    registry.add_check(make_pmf_check());
    registry.add_check(make_discrete_chi2_check());
    registry.add_check(make_remapped_u_check());
    registry.add_check(make_repeatability_check());
    registry.add_check(bsdf::make_bsdf_chi2_check());
    registry.add_check(bsdf::make_bsdf_unbinned_check());
    registry.add_check(bsdf::make_bsdf_weight_check());
    registry.add_check(bsdf::make_bsdf_delta_check());
    registry.add_check(bsdf::make_bsdf_albedo_check());
    registry.add_check(bsdf::make_bsdf_reciprocity_check());
    registry.add_check(bsdf::make_bsdf_energy_check());
    registry.add_check(bsdf::make_bsdf_expectation_check());
    registry.add_check(bsdf::make_bsdf_spectral_check());
    registry.add_check(make_bsdf_repeatability_check());
    registry.add_check(light::make_light_radiance_check());
    registry.add_check(light::make_light_support_check());
    registry.add_check(light::make_light_irradiance_check());
    registry.add_check(light::make_mis_weights_check());
    registry.add_check(light::make_mis_estimator_check());
}

}  // namespace warpcheck
