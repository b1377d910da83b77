// A renderer's diffuse BSDF as it is (pbrt-v4's BxDF shape: sample, f, pdf,
// flags), and a bug of its kind, for the GoogleTest example.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include <validate/api/bsdf_grid.h>

/// f = r / pi on wo's side; wi cosine-weighted by Malley's method.
struct DiffuseBsdf {
    float r;
    warpcheck::BsdfFlags flags() const { return warpcheck::BsdfFlags::Reflection | warpcheck::BsdfFlags::Continuous; }
    float f(warpcheck::Vector3f wo, warpcheck::Vector3f wi) const {
        return wo.z * wi.z > 0 ? r * std::numbers::inv_pi_v<float> : 0.0f;
    }
    float pdf(warpcheck::Vector3f wo, warpcheck::Vector3f wi) const {
        return wo.z * wi.z > 0 ? std::abs(wi.z) * std::numbers::inv_pi_v<float> : 0.0f;
    }
    warpcheck::BsdfSample sample(warpcheck::Vector3f wo, float, warpcheck::Point2f u) const {
        const float rad = std::sqrt(u.x), phi = 2 * std::numbers::pi_v<float> * u.y;
        warpcheck::Vector3f wi{rad * std::cos(phi), rad * std::sin(phi), std::sqrt(std::max(0.0f, 1 - u.x))};
        if (wo.z < 0) wi.z = -wi.z;
        const float p = pdf(wo, wi);
        if (!(p > 0)) return {};
        return {wi, f(wo, wi), p, flags()};
    }
};

/// The bug: wi uniform over the hemisphere while pdf() still says cos / pi.
/// Each sample reports f() and pdf() at its wi, so every weight agrees with
/// them (bsdf_weight and bsdf_albedo cannot see it); where the samples go is
/// wrong (bsdf_chi2, bsdf_unbinned).
struct UniformlySampledDiffuse {
    DiffuseBsdf right;
    warpcheck::BsdfFlags flags() const { return right.flags(); }
    float f(warpcheck::Vector3f wo, warpcheck::Vector3f wi) const { return right.f(wo, wi); }
    float pdf(warpcheck::Vector3f wo, warpcheck::Vector3f wi) const { return right.pdf(wo, wi); }
    warpcheck::BsdfSample sample(warpcheck::Vector3f wo, float, warpcheck::Point2f u) const {
        const float z = u.x, rad = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * std::numbers::pi_v<float> * u.y;
        const warpcheck::Vector3f wi{rad * std::cos(phi), rad * std::sin(phi), wo.z < 0 ? -z : z};
        const float p = pdf(wo, wi);
        if (!(p > 0)) return {};
        return {wi, f(wo, wi), p, flags()};
    }
};
