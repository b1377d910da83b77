// Geometric warps: disks, hemispheres, the sphere and cones.
#include "sampling/disk.h"
#include "sampling/hemisphere.h"
#include "sampling/sphere.h"
#include "validate/registry.h"

namespace warpcheck {

void register_geometric_cases(Registry& registry) {
    using chi2::Domain;
    registry.add_case(make_warp_case({"uniform_disk_concentric", {}, "uniform on the unit disk, Shirley-Chiu concentric map; pdf 1/pi per area",
                                      InputKind::Uniform2D, Domain::unit_disk()},
                                     square_to_uniform_disk_concentric, square_to_uniform_disk_concentric_pdf,
                                     uniform_disk_concentric_to_square));
    registry.add_case(make_warp_case({"uniform_disk_polar", {}, "uniform on the unit disk, r = sqrt(u.x); pdf 1/pi per area",
                                      InputKind::Uniform2D, Domain::unit_disk()},
                                     square_to_uniform_disk_polar, square_to_uniform_disk_polar_pdf,
                                     uniform_disk_polar_to_square));
    registry.add_case(make_warp_case({"uniform_hemisphere", {}, "uniform over the hemisphere; pdf 1/(2 pi) per solid angle",
                                      InputKind::Uniform2D, Domain::hemisphere()},
                                     square_to_uniform_hemisphere, square_to_uniform_hemisphere_pdf,
                                     uniform_hemisphere_to_square));
    registry.add_case(make_warp_case({"cosine_hemisphere", {}, "cosine-weighted hemisphere via the concentric disk; pdf cos(theta)/pi",
                                      InputKind::Uniform2D, Domain::hemisphere()},
                                     square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf,
                                     cosine_hemisphere_to_square));
    for (double n : {0.5, 4.0, 50.0}) {
        const CosinePowerHemisphere lobe(static_cast<float>(n));
        registry.add_case(make_warp_case({"cosine_power_hemisphere", {{"exponent", n}},
                                          "Phong lobe around the normal; pdf (n+1)/(2 pi) cos^n(theta)",
                                          InputKind::Uniform2D, Domain::hemisphere()},
                                         [lobe](Point2f u) { return lobe.sample(u); },
                                         [lobe](Vector3f v) { return lobe.pdf(v); },
                                         [lobe](Vector3f v) { return lobe.invert(v); }));
    }
    registry.add_case(make_warp_case({"uniform_sphere", {}, "uniform over the sphere; pdf 1/(4 pi) per solid angle",
                                      InputKind::Uniform2D, Domain::sphere()},
                                     square_to_uniform_sphere, square_to_uniform_sphere_pdf, uniform_sphere_to_square));
    for (double c : {-0.5, 0.3, 0.99}) {
        const UniformCone cone(static_cast<float>(c));
        registry.add_case(make_warp_case({"uniform_cone", {{"cos_theta_max", c}},
                                          "uniform over the cap z >= cos_theta_max; pdf 1/(2 pi (1 - cos_theta_max))",
                                          InputKind::Uniform2D, Domain::spherical_cap(cone.cos_theta_max())},
                                         [cone](Point2f u) { return cone.sample(u); },
                                         [cone](Vector3f v) { return cone.pdf(v); },
                                         [cone](Vector3f v) { return cone.invert(v); }));
    }
}

}  // namespace warpcheck
