// Warps from the unit square to the unit disk, uniform with respect to area:
// pdf = 1/pi on the disk. Inputs u in [0,1)^2.
#pragma once

#include <cmath>

#include "sampling/math.h"
#include "sampling/vector.h"

namespace warpcheck {

/// Uniform on the unit disk by the polar map.
struct UniformDiskPolar {
    /// Polar map: r = sqrt(u.x), phi = 2 pi u.y. Simple, but it squeezes the square's
    /// cells near the centre and tears the square apart along u.y = 0.
    Point2f sample(Point2f u) const {
        const float r = std::sqrt(u.x);
        const float phi = kTwoPi * u.y;
        const SinCos sc = sin_cos(phi);
        return {r * sc.cos, r * sc.sin};
    }

    /// Density of sample with respect to area: 1/pi on the disk.
    float pdf(Point2f p) const { return p.x * p.x + p.y * p.y <= 1.0f ? kInvPi : 0.0f; }

    /// Inverse of sample: u.x = r^2, u.y = phi / (2 pi).
    Point2f invert(Point2f p) const {
        return {std::min(p.x * p.x + p.y * p.y, kOneMinusEpsilon), azimuth_to_unit(p.x, p.y)};
    }
};

/// Uniform on the unit disk by Shirley and Chiu's concentric map.
struct UniformDiskConcentric {
    /// Shirley and Chiu's concentric map: concentric squares of [-1,1]^2 go to
    /// concentric circles, so it has low distortion and keeps strata compact. The
    /// square (a, b) = 2u - 1 is split by its diagonals; in the wedge where |a| > |b|
    /// the radius is a and the angle (pi/4) b/a, otherwise the radius is b and the
    /// angle pi/2 - (pi/4) a/b. The centre u = (0.5, 0.5) maps to the origin.
    Point2f sample(Point2f u) const {
        const float a = 2.0f * u.x - 1.0f;
        const float b = 2.0f * u.y - 1.0f;
        if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
        float r, phi;
        if (std::abs(a) > std::abs(b)) {
            r = a;
            phi = kPiOver4 * (b / a);
        } else {
            r = b;
            phi = kPiOver2 - kPiOver4 * (a / b);
        }
        const SinCos sc = sin_cos(phi);
        return {r * sc.cos, r * sc.sin};
    }

    /// Density of sample with respect to area: 1/pi on the disk.
    float pdf(Point2f p) const { return UniformDiskPolar{}.pdf(p); }

    /// Inverse of sample. With phi the polar angle in [-pi/4, 7pi/4), the four wedges are the four sides of the square:
    ///   [-pi/4, pi/4): a = r;  [pi/4, 3pi/4): b = r;  [3pi/4, 5pi/4): a = -r;  else b = -r,
    /// and the other coordinate follows from the wedge's angle formula.
    Point2f invert(Point2f p) const {
        const float r = std::hypot(p.x, p.y);
        float phi = std::atan2(p.y, p.x);
        if (phi < -kPiOver4) phi += kTwoPi;
        float a, b;
        if (phi < kPiOver4) {
            a = r;
            b = phi * kFourOverPi * r;
        } else if (phi < 3.0f * kPiOver4) {
            b = r;
            a = (kPiOver2 - phi) * kFourOverPi * r;
        } else if (phi < 5.0f * kPiOver4) {
            a = -r;
            b = (kPi - phi) * kFourOverPi * r;
        } else {
            b = -r;
            a = (phi - 3.0f * kPiOver2) * kFourOverPi * r;
        }
        // Clamped on both sides: a point a rounding error outside the unit circle
        // (as callers that build it from other float math pass) must still give
        // a valid input of [0,1)^2.
        return {std::clamp(0.5f * (a + 1.0f), 0.0f, kOneMinusEpsilon),
                std::clamp(0.5f * (b + 1.0f), 0.0f, kOneMinusEpsilon)};
    }
};

}  // namespace warpcheck
