// What a light sampler returns (sampling/light.h): its own header, so that a
// renderer's code (and validate/api/light_case.h) can name it without the
// built-in lights.
#pragma once

#include "sampling/vector.h"

namespace warpcheck {

/// One light sample seen from a reference point: the unit direction wi from ref towards the light,
/// its density in SOLID ANGLE at ref, the radiance L arriving at ref along wi, and the distance to the light.
/// pdf == 0 means no sample (e.g. ref on the back of a one-sided light); never NaN.
struct LightSample {
    Vector3f wi{};
    float pdf = 0.0f;
    float L = 0.0f;
    float distance = 0.0f;
};

}  // namespace warpcheck
