// Geometric warps: disks, hemispheres, the sphere and cones.
#include <cmath>
#include <functional>

#include "sampling/disk.h"
#include "sampling/hemisphere.h"
#include "sampling/sphere.h"
#include "validate/lanes/lane_sampling.h"
#include "validate/api/registry.h"

namespace warpcheck {
namespace {

// The monotone 1D views for the tabulated check: cos(theta) of the warps whose
// z depends on u.x alone, their azimuth, and the radius of the polar disk.
MonotoneMarginal cos_theta_marginal(bool increasing, double z_min, std::function<double(double)> pdf) {
    MonotoneMarginal m;
    m.input_coordinate = 0;
    m.increasing = increasing;
    m.lo = z_min;
    m.hi = 1.0;
    m.label = "cos theta";
    m.coordinate = [](const WarpOutput& o) { return static_cast<double>(o[2]); };
    m.pdf = std::move(pdf);
    return m;
}

// The azimuth phi = 2 pi u.y of the warps that set it so, uniform on [0, 2 pi):
// with it, an error in phi is tabulated too, not only one in cos theta.
MonotoneMarginal azimuth() {
    MonotoneMarginal m;
    m.input_coordinate = 1;
    m.lo = 0.0;
    m.hi = chi2::kTwoPi;
    m.label = "phi";
    m.coordinate = [](const WarpOutput& o) {
        if (o[0] == 0.0f && o[1] == 0.0f) return std::nan("");  // the pole: no azimuth
        return chi2::exact_phi(static_cast<double>(o[0]), static_cast<double>(o[1]));
    };
    m.pdf = [](double) { return 1.0 / chi2::kTwoPi; };
    return m;
}

void register_geometric_cases(Registry& registry) {
    using chi2::Domain;
    registry.add_case(
        make_warp_case({.family = "uniform_disk_concentric",
                        .description = "uniform on the unit disk, Shirley-Chiu concentric map; pdf 1/pi per area",
                        .domain = Domain::unit_disk(),
                        .lanes = &builtin_lanes::uniform_disk_concentric()},
                       UniformDiskConcentric{}));
    MonotoneMarginal radius;
    radius.label = "r";
    radius.coordinate = [](const WarpOutput& o) { return std::hypot(static_cast<double>(o[0]), static_cast<double>(o[1])); };
    radius.pdf = [](double r) { return 2.0 * r; };
    registry.add_case(make_warp_case({.family = "uniform_disk_polar",
                                      .description = "uniform on the unit disk, r = sqrt(u.x); pdf 1/pi per area",
                                      .domain = Domain::unit_disk(),
                                      .views = {radius},
                                      .lanes = &builtin_lanes::uniform_disk_polar()},
                                     UniformDiskPolar{}));
    registry.add_case(make_warp_case({.family = "uniform_hemisphere",
                                      .description = "uniform over the hemisphere; pdf 1/(2 pi) per solid angle",
                                      .domain = Domain::hemisphere(),
                                      .views = {cos_theta_marginal(true, 0.0, [](double) { return 1.0; }), azimuth()},
                                      .lanes = &builtin_lanes::uniform_hemisphere()},
                                     UniformHemisphere{}));
    registry.add_case(
        make_warp_case({.family = "cosine_hemisphere",
                        .description = "cosine-weighted hemisphere via the concentric disk; pdf cos(theta)/pi",
                        .domain = Domain::hemisphere(),
                        .lanes = &builtin_lanes::cosine_hemisphere()},
                       CosineHemisphere{}));
    for (double n : {0.5, 4.0, 50.0}) {
        registry.add_case(make_warp_case(
            {.family = "cosine_power_hemisphere",
             .params = {{"exponent", n}},
             .description = "Phong lobe around the normal; pdf (n+1)/(2 pi) cos^n(theta)",
             .domain = Domain::hemisphere(),
             .views = {cos_theta_marginal(true, 0.0, [n](double z) { return (n + 1.0) * std::pow(z, n); }), azimuth()},
             .lanes = &builtin_lanes::cosine_power_hemisphere(static_cast<float>(n))},
            CosinePowerHemisphere(static_cast<float>(n))));
    }
    registry.add_case(make_warp_case({.family = "uniform_sphere",
                                      .description = "uniform over the sphere; pdf 1/(4 pi) per solid angle",
                                      .domain = Domain::sphere(),
                                      .views = {cos_theta_marginal(false, -1.0, [](double) { return 0.5; }), azimuth()},
                                      .lanes = &builtin_lanes::uniform_sphere()},
                                     UniformSphere{}));
    for (double c : {-0.5, 0.3, 0.99}) {
        const UniformCone cone(static_cast<float>(c));
        const double z_min = cone.cos_theta_max();
        registry.add_case(make_warp_case(
            {.family = "uniform_cone",
             .params = {{"cos_theta_max", c}},
             .description = "uniform over the cap z >= cos_theta_max; pdf 1/(2 pi (1 - cos_theta_max))",
             .domain = Domain::spherical_cap(z_min),
             .views = {cos_theta_marginal(false, z_min, [z_min](double) { return 1.0 / (1.0 - z_min); }), azimuth()},
             .lanes = &builtin_lanes::uniform_cone(cone.cos_theta_max())},
            cone));
    }
}

WARPCHECK_BUILTIN_CASES(10, register_geometric_cases);

}  // namespace

}  // namespace warpcheck
