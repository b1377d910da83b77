// Wrong twins of hard BSDFs whose flaw is only where the samples go: each
// sample reports f() and pdf() at its wi, so every weight agrees with them
// (bsdf_weight passes) while the sampled distribution is a little off. The
// distribution checks' hardest cases (tests/validate/checks/bsdf/test_bsdf_unbinned.cpp)
// and their power (tests/validate/checks/bsdf/test_bsdf_power.cpp).
#pragma once

#include <memory>

#include "sampling/bsdf_conductor.h"
#include "sampling/bsdf_phase.h"
#include "validate/api/bsdf_case.h"
#include "validate/cases/bsdf_flawed.h"

namespace warpcheck::testing {

/// A gold conductor whose visible normals are sampled with alpha (1 + eps)
/// while f() and pdf() use alpha.
inline std::unique_ptr<WarpCase> conductor_wrong_roughness(float alpha, double theta, double eps) {
    return sampled_by({.family = "conductor_wrong_roughness", .params = {{"alpha", alpha}, {"theta_o", theta}, {"eps", eps}}},
                      bsdf_direction(theta), RoughConductor(TrowbridgeReitz(alpha), 0.2f, 3.0f),
                      RoughConductor(TrowbridgeReitz(static_cast<float>(alpha * (1.0 + eps))), 0.2f, 3.0f));
}

/// Henyey-Greenstein seen from theta_o = 30 degrees (phi_o 20), sampled with
/// g + dg while its p and pdf are those of g.
inline std::unique_ptr<WarpCase> henyey_greenstein_wrong_g(float g, float dg) {
    const HenyeyGreenstein right(g), wrong(g + dg);
    const auto sample = [right, wrong](Vector3f wo, Point2f u) {
        BsdfSample s = wrong.sample(wo, u);
        s.f = s.pdf = right.pdf(wo, s.wi);
        return s;
    };
    return make_bsdf_case({.family = "hg_wrong_g", .params = {{"g", g}, {"theta_o", 30}, {"phi_o", 20}, {"dg", dg}}},
                          {.wo = bsdf_direction(30, 20), .lobes = BsdfFlags::Continuous, .phase_function = true},
                          bsdf_of(sample)
                              .with_f([right](Vector3f wo, Vector3f wi) { return right.p(wo, wi); })
                              .with_pdf([right](Vector3f wo, Vector3f wi) { return right.pdf(wo, wi); }));
}

}  // namespace warpcheck::testing
