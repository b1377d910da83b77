// Class 6 of issue 22: round trips at float resolution in 2D. (The triangle
// near its vertex is `triangle` in supports.cpp, the sharp lobe `phong` and
// the suns in quantised_outputs.cpp, each with an inverse and a wrong twin.)
//
// The uniform disk by the polar map with pbrt-v4's inverse
// (InvertUniformDiskPolarSample): r^2 = x^2 + y^2, phi = atan2(y, x), plus
// 2 pi below 0, over 2 pi. Correct: the exact inverse of r = sqrt(u.x),
// phi = 2 pi u.y. Hard: for u.y within a float of 1, 2 pi u.y rounds to the
// float below 2 pi, atan2 returns a tiny negative angle, and adding 2 pi
// rounds to 2 pi: the inverse returns exactly 1.0, as renderers write it
// (renderers clamp u below 1; issue 22 asks that this be its own class).
// Twin: the inverse's azimuth scaled by 1 - 1e-3.
#include <string>

#include "hard_warps.h"

namespace hard {
namespace {

struct PolarDisk {
    float inverse_scale = 1;  // twin
    Point2f sample(Point2f u) const {
        const float r = std::sqrt(u.x), phi = 2 * kPi * u.y;
        return {r * std::cos(phi), r * std::sin(phi)};
    }
    float pdf(Point2f) const { return 1 / kPi; }  // pbrt-v4's UniformDiskPDF: the domain is the disk
    Point2f invert(Point2f p) const { return {p.x * p.x + p.y * p.y, inverse_scale * azimuth_turns(p.x, p.y)}; }
};

}  // namespace

void register_roundtrip_2d(warpcheck::Registry& registry) {
    for (bool twin : {false, true})
        registry.add_case(warpcheck::make_warp_case(
            {.family = twin ? "disk_polar_inverse_1e-3" : "disk_polar_pbrt_inverse",
             .description = "uniform disk, polar map, pbrt-v4's inverse (atan2, + 2 pi below 0, / 2 pi)",
             .domain = warpcheck::chi2::Domain::unit_disk()},
            PolarDisk{twin ? 1 - 1e-3f : 1}));
    mark_twin(registry, "disk_polar_inverse_1e-3", "roundtrip", "the inverse's u.y is scaled by 1 - 1e-3");
}

}  // namespace hard
