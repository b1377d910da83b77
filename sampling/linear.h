// Linear and bilinear densities: the 1D warp with density proportional to a
// line, and the patch warp built from it. Both are what a renderer uses to
// sample a bilinear light or texture patch.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "sampling/float_bits.h"
#include "sampling/vector.h"

namespace warpcheck {

/// The density proportional to the line (1 - x) a + x b on [0,1], with a, b >= 0
/// and not both 0. The caller vouches for a and b: Bilinear builds one per sample
/// from weights it has validated, so the constructor does not check them again.
class Linear {
public:
    Linear(float a, float b) : a_(a), b_(b) {}

    /// Samples x in [0,1] with density proportional to (1 - x) a + x b. Solves the
    /// quadratic CDF with the root written as u (a + b) / (a + sqrt(lerp(u, a^2, b^2))),
    /// which has no cancellation; it is 0/0 only at u = 0 with a = 0, where the answer is 0.
    float sample(float u) const {
        if (u == 0.0f) return 0.0f;
        const float x = u * (a_ + b_) / (a_ + std::sqrt((1.0f - u) * a_ * a_ + u * b_ * b_));
        return std::min(x, kOneMinusEpsilon);
    }

    /// Density of sample on [0,1] with respect to length: 2 lerp(x, a, b) / (a + b).
    float pdf(float x) const {
        if (x < 0.0f || x > 1.0f) return 0.0f;
        return 2.0f * ((1.0f - x) * a_ + x * b_) / (a_ + b_);
    }

    /// Inverse of sample: the CDF, x (a (2 - x) + b x) / (a + b).
    float invert(float x) const { return std::min(x * (a_ * (2.0f - x) + b_ * x) / (a_ + b_), kOneMinusEpsilon); }

private:
    float a_, b_;
};

/// Samples the unit square with density proportional to the bilinear
/// interpolation of four corner weights w00, w10, w01, w11 (at (0,0), (1,0),
/// (0,1), (1,1)): y from its linear marginal, then x from the line at that y.
class Bilinear {
public:
    Bilinear(float w00, float w10, float w01, float w11) : w00_(w00), w10_(w10), w01_(w01), w11_(w11) {
        const bool valid = std::isfinite(w00 + w10 + w01 + w11) && w00 >= 0 && w10 >= 0 && w01 >= 0 && w11 >= 0 &&
                           w00 + w10 + w01 + w11 > 0;
        if (!valid) throw std::invalid_argument("bilinear: weights must be finite, >= 0 and not all 0");
    }

    /// y from its marginal, linear in y; then x from the line of the patch at that y.
    Point2f sample(Point2f u) const {
        const float y = Linear(w00_ + w10_, w01_ + w11_).sample(u.y);
        return {Linear(lerp(y, w00_, w01_), lerp(y, w10_, w11_)).sample(u.x), y};
    }

    /// Density with respect to area on [0,1]^2: 4 bilerp(p) / (w00 + w10 + w01 + w11).
    float pdf(Point2f p) const {
        if (p.x < 0.0f || p.x > 1.0f || p.y < 0.0f || p.y > 1.0f) return 0.0f;
        const float bilerp = lerp(p.y, lerp(p.x, w00_, w10_), lerp(p.x, w01_, w11_));
        return 4.0f * bilerp / (w00_ + w10_ + w01_ + w11_);
    }

    /// Inverse of sample: the conditional CDF of x at p.y, and the marginal CDF of y.
    Point2f invert(Point2f p) const {
        return {Linear(lerp(p.y, w00_, w01_), lerp(p.y, w10_, w11_)).invert(p.x),
                Linear(w00_ + w10_, w01_ + w11_).invert(p.y)};
    }

private:
    static float lerp(float t, float a, float b) { return (1.0f - t) * a + t * b; }
    float w00_, w10_, w01_, w11_;
};

}  // namespace warpcheck
