// Warps from the unit square to the upper hemisphere (z >= 0). Densities are with
// respect to solid angle. Inputs u in [0,1)^2.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "sampling/disk.h"
#include "sampling/math.h"
#include "sampling/vector.h"

namespace warpcheck {

/// Uniform over the hemisphere.
struct UniformHemisphere {
    /// Uniform over the hemisphere: z = cos(theta) = u.x, phi = 2 pi u.y (the area of
    /// a band of the sphere is proportional to its height, so uniform z is uniform area).
    Vector3f sample(Point2f u) const {
        const float z = u.x;
        const float r = sin_from_cos(z);
        const float phi = kTwoPi * u.y;
        const SinCos sc = sin_cos(phi);
        return {r * sc.cos, r * sc.sin, z};
    }

    /// Density of sample: 1/(2 pi) for z >= 0, else 0.
    float pdf(Vector3f v) const { return v.z >= 0.0f ? kInvTwoPi : 0.0f; }

    /// Inverse of sample.
    Point2f invert(Vector3f v) const { return {v.z, azimuth_to_unit(v.x, v.y)}; }
};

/// Cosine-weighted hemisphere.
struct CosineHemisphere {
    /// Cosine-weighted hemisphere (Malley's method): a uniform point of the disk,
    /// from the concentric map, lifted to the hemisphere. Projection to the disk
    /// divides area by cos(theta), so uniform on the disk is cos(theta)/pi on the
    /// hemisphere. The rim z = 0 (density 0) is reached only from u.x = 0 or u.y = 0.
    Vector3f sample(Point2f u) const {
        const Point2f d = UniformDiskConcentric{}.sample(u);
        const float z = safe_sqrt(1.0f - d.x * d.x - d.y * d.y);
        return {d.x, d.y, z};
    }

    /// Density of sample: cos(theta)/pi for z >= 0, else 0.
    float pdf(Vector3f v) const { return v.z >= 0.0f ? v.z * kInvPi : 0.0f; }

    /// Inverse of sample: project to the disk, invert the concentric map.
    Point2f invert(Vector3f v) const { return UniformDiskConcentric{}.invert({v.x, v.y}); }
};

/// Cosine-power lobe around the normal, density (n+1)/(2 pi) cos^n(theta): the
/// Phong lobe, which is the uniform hemisphere for n = 0 and the cosine
/// hemisphere for n = 1. Its CDF in z is z^(n+1), so z = u.x^(1/(n+1)).
class CosinePowerHemisphere {
public:
    explicit CosinePowerHemisphere(float exponent) : n_(exponent) {
        if (!(exponent >= 0.0f) || !std::isfinite(exponent))
            throw std::invalid_argument("cosine_power_hemisphere: exponent must be finite and >= 0, got " +
                                        std::to_string(exponent));
    }

    float exponent() const { return n_; }

    Vector3f sample(Point2f u) const {
        const float z = std::pow(u.x, 1.0f / (n_ + 1.0f));
        const float r = sin_from_cos(z);
        const float phi = kTwoPi * u.y;
        const SinCos sc = sin_cos(phi);
        return {r * sc.cos, r * sc.sin, z};
    }

    /// Density with respect to solid angle: (n+1)/(2 pi) z^n for z >= 0, else 0.
    float pdf(Vector3f v) const { return v.z >= 0.0f ? (n_ + 1.0f) * kInvTwoPi * std::pow(v.z, n_) : 0.0f; }

    Point2f invert(Vector3f v) const {
        return {std::min(std::pow(std::max(v.z, 0.0f), n_ + 1.0f), kOneMinusEpsilon), azimuth_to_unit(v.x, v.y)};
    }

private:
    float n_;
};

}  // namespace warpcheck
