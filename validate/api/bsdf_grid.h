// BSDFs over a grid of outgoing directions (and parameters): wo from a grid
// point's theta_o and phi_o axes, in degrees (validate/api/case_grid.h makes the
// grid: stable names such as rough_conductor[alpha=0.3,theta_o=60]).
#pragma once

#include "validate/api/bsdf_case.h"
#include "validate/api/case_grid.h"

namespace warpcheck {

/// The outgoing direction of a grid point: bsdf_direction(theta_o, phi_o)
/// from its axes "theta_o" and (when there is one) "phi_o", in degrees; the
/// polar angle from +z, so theta_o above 90 looks from below the surface.
inline Vector3f grid_wo(const GridPoint& point) {
    double phi = 0.0;
    for (const Parameter& p : point.params())
        if (p.name == "phi_o") phi = p.value;
    return bsdf_direction(point["theta_o"], phi);
}

}  // namespace warpcheck
