// Trowbridge-Reitz (GGX) warps: normals with density D cos(theta_m), and visible
// normals for views from normal incidence to 85 degrees, for isotropic and
// anisotropic roughness from nearly specular (0.05) to rough (1).
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "sampling/trowbridge_reitz.h"
#include "validate/lanes/lane_sampling.h"
#include "validate/api/registry.h"

namespace warpcheck {
namespace {

const std::vector<std::pair<double, double>> kAlphas = {{0.05, 0.05}, {0.3, 0.3}, {1.0, 1.0}, {0.3, 0.05}, {0.05, 0.4}};

/// The monotone 1D view of the normal warp for the tabulated check. Isotropic:
/// cos(theta_m), a decreasing function of u.x alone. Anisotropic: the azimuth,
/// an increasing function of u.y alone (cos theta_m then depends on both inputs).
MonotoneMarginal normal_marginal(double ax, double ay) {
    MonotoneMarginal m;
    if (ax == ay) {
        m.input_coordinate = 0;
        m.increasing = false;
        m.lo = 0.0;
        m.hi = 1.0;
        m.label = "cos theta_m";
        m.coordinate = [](const WarpOutput& o) { return static_cast<double>(o[2]); };
        m.pdf = [ax](double z) { return TrowbridgeReitz::isotropic_cos_theta_pdf(ax, z); };
    } else {
        m.input_coordinate = 1;
        m.increasing = true;
        m.lo = 0.0;
        m.hi = 2.0 * std::numbers::pi;
        m.label = "phi_m";
        m.coordinate = [](const WarpOutput& o) {
            if (o[0] == 0.0f && o[1] == 0.0f) return std::nan("");  // the pole has no azimuth
            const double phi = std::atan2(static_cast<double>(o[1]), static_cast<double>(o[0]));
            return phi < 0.0 ? phi + 2.0 * std::numbers::pi : phi;
        };
        m.pdf = [ax, ay](double phi) { return TrowbridgeReitz::azimuth_pdf(ax, ay, phi); };
    }
    return m;
}

void register_trowbridge_reitz_cases(Registry& registry) {
    using chi2::Domain;
    for (auto [ax, ay] : kAlphas) {
        const TrowbridgeReitz tr(static_cast<float>(ax), static_cast<float>(ay));
        registry.add_case(make_warp_case(
            {.family = "trowbridge_reitz_normals",
             .params = {{"ax", ax}, {"ay", ay}},
             .description = "Trowbridge-Reitz microfacet normals; pdf D(wm) cos(theta_m) per solid angle",
             .domain = Domain::hemisphere(),
             .views = {normal_marginal(ax, ay)},
             .lanes = &builtin_lanes::trowbridge_reitz_normals(tr.alpha_x(), tr.alpha_y())},
            tr.normals()));
    }
    for (auto [ax, ay] : kAlphas) {
        const TrowbridgeReitz tr(static_cast<float>(ax), static_cast<float>(ay));
        for (double theta_o : {0.0, 30.0, 60.0, 85.0}) {
            const double t = theta_o * std::numbers::pi / 180.0;
            const auto vis = tr.visible_normals({static_cast<float>(std::sin(t)), 0.0f, static_cast<float>(std::cos(t))});
            // No tabulated view: the concentric map mixes both inputs into every
            // coordinate. Round trip at the default tolerance: the inverse is exact to ~6e-7.
            registry.add_case(make_warp_case(
                {.family = "trowbridge_reitz_visible",
                 .params = {{"ax", ax}, {"ay", ay}, {"theta_o", theta_o}},
                 .description = "Trowbridge-Reitz visible normals for wo at theta_o in the xz-plane (spherical caps); "
                                "pdf G1(wo) max(0, wo.wm) D(wm) / cos(theta_o) per solid angle",
                 .domain = Domain::hemisphere(),
                 .lanes = &builtin_lanes::trowbridge_reitz_visible(vis)},
                vis));
        }
    }
}

WARPCHECK_BUILTIN_CASES(50, register_trowbridge_reitz_cases);

}  // namespace

}  // namespace warpcheck
