// Geometric warps: disks, hemispheres, the sphere and cones.
#include <cmath>
#include <functional>

#include "sampling/disk.h"
#include "sampling/hemisphere.h"
#include "sampling/sphere.h"
#include "validate/registry.h"

namespace warpcheck {
namespace {

// The monotone 1D views for the tabulated check: cos(theta) of the warps whose
// z depends on u.x alone, and the radius of the polar disk.
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

WarpCaseInfo with_marginal(WarpCaseInfo info, MonotoneMarginal marginal) {
    info.marginal = std::move(marginal);
    return info;
}

}  // namespace

void register_geometric_cases(Registry& registry) {
    using chi2::Domain;
    registry.add_case(make_warp_case({"uniform_disk_concentric", {}, "uniform on the unit disk, Shirley-Chiu concentric map; pdf 1/pi per area",
                                      InputKind::Uniform2D, Domain::unit_disk()},
                                     square_to_uniform_disk_concentric, square_to_uniform_disk_concentric_pdf,
                                     uniform_disk_concentric_to_square));
    MonotoneMarginal radius;
    radius.label = "r";
    radius.coordinate = [](const WarpOutput& o) { return std::hypot(static_cast<double>(o[0]), static_cast<double>(o[1])); };
    radius.pdf = [](double r) { return 2.0 * r; };
    registry.add_case(make_warp_case(with_marginal({"uniform_disk_polar", {}, "uniform on the unit disk, r = sqrt(u.x); pdf 1/pi per area",
                                      InputKind::Uniform2D, Domain::unit_disk()}, radius),
                                     square_to_uniform_disk_polar, square_to_uniform_disk_polar_pdf,
                                     uniform_disk_polar_to_square));
    registry.add_case(make_warp_case(with_marginal({"uniform_hemisphere", {}, "uniform over the hemisphere; pdf 1/(2 pi) per solid angle",
                                      InputKind::Uniform2D, Domain::hemisphere()},
                                     cos_theta_marginal(true, 0.0, [](double) { return 1.0; })),
                                     square_to_uniform_hemisphere, square_to_uniform_hemisphere_pdf,
                                     uniform_hemisphere_to_square));
    registry.add_case(make_warp_case({"cosine_hemisphere", {}, "cosine-weighted hemisphere via the concentric disk; pdf cos(theta)/pi",
                                      InputKind::Uniform2D, Domain::hemisphere()},
                                     square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf,
                                     cosine_hemisphere_to_square));
    for (double n : {0.5, 4.0, 50.0}) {
        const CosinePowerHemisphere lobe(static_cast<float>(n));
        registry.add_case(make_warp_case(with_marginal({"cosine_power_hemisphere", {{"exponent", n}},
                                          "Phong lobe around the normal; pdf (n+1)/(2 pi) cos^n(theta)",
                                          InputKind::Uniform2D, Domain::hemisphere()},
                                         cos_theta_marginal(true, 0.0, [n](double z) { return (n + 1.0) * std::pow(z, n); })),
                                         [lobe](Point2f u) { return lobe.sample(u); },
                                         [lobe](Vector3f v) { return lobe.pdf(v); },
                                         [lobe](Vector3f v) { return lobe.invert(v); }));
    }
    registry.add_case(make_warp_case(with_marginal({"uniform_sphere", {}, "uniform over the sphere; pdf 1/(4 pi) per solid angle",
                                      InputKind::Uniform2D, Domain::sphere()},
                                     cos_theta_marginal(false, -1.0, [](double) { return 0.5; })),
                                     square_to_uniform_sphere, square_to_uniform_sphere_pdf, uniform_sphere_to_square));
    for (double c : {-0.5, 0.3, 0.99}) {
        const UniformCone cone(static_cast<float>(c));
        const double z_min = cone.cos_theta_max();
        registry.add_case(make_warp_case(with_marginal({"uniform_cone", {{"cos_theta_max", c}},
                                          "uniform over the cap z >= cos_theta_max; pdf 1/(2 pi (1 - cos_theta_max))",
                                          InputKind::Uniform2D, Domain::spherical_cap(z_min)},
                                         cos_theta_marginal(false, z_min, [z_min](double) { return 1.0 / (1.0 - z_min); })),
                                         [cone](Point2f u) { return cone.sample(u); },
                                         [cone](Vector3f v) { return cone.pdf(v); },
                                         [cone](Vector3f v) { return cone.invert(v); }));
    }
}

}  // namespace warpcheck
