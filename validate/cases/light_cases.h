// What the built-in light cases (light.cpp) share with the known-bad ones
// (light_flawed.cpp): the three lights of the light sets and their pmf.
#pragma once

#include <array>

#include "sampling/light.h"

namespace warpcheck {

/// A sphere (towards theta 30), a triangle (below the reference surface, at
/// theta 120) and a disk (at theta -60) around the origin, apart as seen
/// from it, each of radiance 2, with their areas.
struct ThreeLights {
    SphereLight sphere;
    TriangleLight triangle;
    DiskLight disk;
    std::array<float, 3> areas;
};
ThreeLights three_lights();

/// The pmf by power (Le pi area, every Le the same) of the three lights.
std::array<float, 3> power_pmf(const ThreeLights& lights);

/// The environment_sky map (32 x 16): a gradient above the horizon, 0.05
/// below it, and a sun `sun` times the sky (500 in the built-ins) at pixel (9, 3).
EnvironmentLight sky_light(double sun = 500.0);

}  // namespace warpcheck
