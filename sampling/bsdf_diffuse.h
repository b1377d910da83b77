// The Lambertian BSDF: reflection with the constant value R / pi, two-sided
// (wi on wo's side, whichever that is), sampled cosine-weighted.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "sampling/bsdf.h"
#include "sampling/hemisphere.h"

namespace warpcheck {

/// f = R / pi on wo's side of the surface; directional albedo R for every wo.
class Lambertian {
public:
    explicit Lambertian(float reflectance) : r_(reflectance) {
        if (!(reflectance >= 0.0f && reflectance <= 1.0f))
            throw std::invalid_argument("lambertian: reflectance must lie in [0, 1], got " +
                                        std::to_string(reflectance));
    }

    float reflectance() const { return r_; }
    BsdfFlags flags() const { return BsdfFlags::Reflection | BsdfFlags::Continuous; }

    /// wi cosine-weighted on wo's side (Malley's method; CosineHemisphere), pdf
    /// |cos theta_i| / pi. uc is not used. No sample for a grazing wo (z = 0,
    /// on neither side) or where wi comes out on the horizon (pdf 0), which
    /// CosineHemisphere reaches only from inputs exactly on the square's edge.
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        (void)uc;
        if (wo.z == 0.0f) return {};
        Vector3f wi = CosineHemisphere{}.sample(u);
        if (wo.z < 0.0f) wi.z = -wi.z;
        const float pdf = std::abs(wi.z) * kInvPi;
        if (!(pdf > 0.0f)) return {};
        return {wi, r_ * kInvPi, pdf, flags()};
    }

    float f(Vector3f wo, Vector3f wi) const { return same_hemisphere(wo, wi) ? r_ * kInvPi : 0.0f; }
    float pdf(Vector3f wo, Vector3f wi) const { return same_hemisphere(wo, wi) ? std::abs(wi.z) * kInvPi : 0.0f; }

private:
    float r_;
};

}  // namespace warpcheck
