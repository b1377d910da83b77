// Warps from the unit square to the whole unit sphere, and to a spherical cap
// (a cone of directions around +z). Densities are with respect to solid angle.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "sampling/math.h"
#include "sampling/vector.h"

namespace warpcheck {

/// Uniform over the whole sphere.
struct UniformSphere {
    /// Uniform over the sphere: z = 1 - 2 u.x, phi = 2 pi u.y (Archimedes: equal
    /// heights cut equal areas).
    Vector3f sample(Point2f u) const {
        const float z = 1.0f - 2.0f * u.x;
        const float r = sin_from_cos(z);
        const float phi = kTwoPi * u.y;
        const SinCos sc = sin_cos(phi);
        return {r * sc.cos, r * sc.sin, z};
    }

    /// Density of sample: 1/(4 pi) everywhere.
    float pdf(Vector3f) const { return kInvFourPi; }

    /// Inverse of sample. At the poles the azimuth is undefined; any u.y is a
    /// valid preimage there.
    Point2f invert(Vector3f v) const {
        return {std::min(0.5f * (1.0f - v.z), kOneMinusEpsilon), azimuth_to_unit(v.x, v.y)};
    }
};

/// Uniform over the cone of directions within theta_max of +z, i.e. the cap
/// z >= cos_theta_max, of solid angle 2 pi (1 - cos_theta_max). Valid for
/// cos_theta_max in [-1, 1): -1 is the whole sphere, 0 the hemisphere.
class UniformCone {
public:
    explicit UniformCone(float cos_theta_max) : cos_theta_max_(cos_theta_max) {
        if (!(cos_theta_max >= -1.0f && cos_theta_max < 1.0f))
            throw std::invalid_argument("uniform_cone: cos_theta_max must lie in [-1, 1), got " +
                                        std::to_string(cos_theta_max));
    }

    float cos_theta_max() const { return cos_theta_max_; }

    /// cos(theta) = 1 - u.x (1 - cos_theta_max): uniform in z over the cap. sin(theta)
    /// comes from 1 - cos(theta), which is computed without cancellation.
    Vector3f sample(Point2f u) const {
        const float one_minus_cos = u.x * (1.0f - cos_theta_max_);
        const float z = 1.0f - one_minus_cos;
        const float r = safe_sqrt(one_minus_cos * (2.0f - one_minus_cos));
        const float phi = kTwoPi * u.y;
        const SinCos sc = sin_cos(phi);
        return {r * sc.cos, r * sc.sin, z};
    }

    /// Density: 1 / (2 pi (1 - cos_theta_max)) inside the cap, 0 outside. The cap
    /// test allows 4 float ulps of 1 below the rim, where rounding in sample() can
    /// put a point of the rim; that sliver's solid angle (~1e-6 of the cap) is far
    /// below anything a statistical test resolves.
    float pdf(Vector3f v) const {
        return v.z >= cos_theta_max_ - 0x1p-22f ? 1.0f / (kTwoPi * (1.0f - cos_theta_max_)) : 0.0f;
    }

    Point2f invert(Vector3f v) const {
        const float u0 = (1.0f - v.z) / (1.0f - cos_theta_max_);
        return {std::clamp(u0, 0.0f, kOneMinusEpsilon), azimuth_to_unit(v.x, v.y)};
    }

private:
    float cos_theta_max_;
};

}  // namespace warpcheck
