// The Henyey-Greenstein phase function: scattering in a medium, on the whole
// sphere. Same shape as the BSDFs (sampling/bsdf.h), with pbrt-v4's names:
// sample(wo, u), p(wo, wi), pdf(wo, wi); the weight is p / pdf (no cosine).
// wo points back along the incoming ray, so forward scattering (g > 0) sends
// wi near -wo: the scattering angle theta has cos theta = -wo.wi.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "sampling/bsdf.h"

namespace warpcheck {

class HenyeyGreenstein {
public:
    /// g in (-1, 1): the mean cosine of the scattering angle.
    explicit HenyeyGreenstein(float g) : g_(g) {
        if (!(g > -1.0f && g < 1.0f))
            throw std::invalid_argument("henyey_greenstein: g must lie in (-1, 1), got " + std::to_string(g));
    }

    float g() const { return g_; }
    BsdfFlags flags() const { return BsdfFlags::Continuous; }

    /// p = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos theta)^(3/2)). The bracket is
    /// written as a sum of non-negative terms, (1 - |g|)^2 + 2 |g| t with
    /// t = 1 - cos(angle to the lobe's axis), so that a sharp lobe (g near 1)
    /// does not lose it to cancellation between 1 + g^2 and 2 g cos theta.
    float p(Vector3f wo, Vector3f wi) const { return value(1.0f + (g_ >= 0.0f ? dot(wo, wi) : -dot(wo, wi))); }
    float pdf(Vector3f wo, Vector3f wi) const { return p(wo, wi); }

    /// By inversion of the CDF of cos theta, in the form for t = 1 - cos of
    /// the angle to the axis (-wo for g >= 0, wo for g < 0: -g mirrors the
    /// lobe) that has no cancellation:
    ///   s = (1 - g^2) / (1 - g + 2 g u.x),  t = (1 - g)(1 - u.x)(s + 1 - g) / (1 - g + 2 g u.x)
    /// with g = |g| (t = 2 (1 - u.x) for g = 0: the uniform sphere); the azimuth is 2 pi u.y.
    BsdfSample sample(Vector3f wo, Point2f u) const {
        const float g = std::abs(g_), q = 1.0f - g + 2.0f * g * u.x;
        const float s = (1.0f - g * g) / q;
        const float t = std::min((1.0f - g) * (1.0f - u.x) * (s + 1.0f - g) / q, 2.0f);
        const float cos_a = 1.0f - t, sin_a = safe_sqrt(t * (2.0f - t));
        const SinCos phi = sin_cos(kTwoPi * u.y);
        const Frame frame = Frame::around(g_ >= 0.0f ? -1.0f * wo : wo);
        const Vector3f wi = frame.to_world(sin_a * phi.cos, sin_a * phi.sin, cos_a);
        const float p = value(t);
        return {wi, p, p, BsdfFlags::Continuous};
    }

private:
    /// p at t = 1 - cos(angle to the axis), t in [0, 2].
    float value(float t) const {
        const float g = std::abs(g_), a = 1.0f - g;
        const float denom = a * a + 2.0f * g * std::max(t, 0.0f);
        return kInvFourPi * (1.0f - g * g) / (denom * std::sqrt(denom));
    }

    float g_;
};

}  // namespace warpcheck
