// A renderer's sphere light as it is (pbrt-v4's light shape: sample from a
// reference point, pdf and the radiance along a ray), for the GoogleTest
// example: uniform over the cone of directions that meets the sphere.
#pragma once

#include <cmath>
#include <numbers>

#include <validate/api/light_case.h>

struct SphereLight {
    warpcheck::Vector3f c;
    float r, le;

    static float dot(warpcheck::Vector3f a, warpcheck::Vector3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
    warpcheck::Vector3f to_centre(warpcheck::Vector3f ref) const { return {c.x - ref.x, c.y - ref.y, c.z - ref.z}; }
    float one_minus_cos_max(warpcheck::Vector3f ref) const {
        const warpcheck::Vector3f oc = to_centre(ref);
        const float s2 = r * r / dot(oc, oc);
        return s2 / (1 + std::sqrt(1 - s2));
    }
    bool hits(warpcheck::Vector3f ref, warpcheck::Vector3f wi) const {
        const warpcheck::Vector3f oc = to_centre(ref);
        const float b = dot(oc, wi);
        return b > 0 && dot(oc, oc) - b * b <= r * r;
    }
    warpcheck::LightSample sample(warpcheck::Vector3f ref, warpcheck::Point2f u) const {
        const warpcheck::Vector3f oc = to_centre(ref);
        const float d = std::sqrt(dot(oc, oc)), omc_max = one_minus_cos_max(ref);
        const warpcheck::Vector3f a{oc.x / d, oc.y / d, oc.z / d};
        // An orthonormal frame around a (Duff et al. 2017).
        const float sign = std::copysign(1.0f, a.z), p = -1 / (sign + a.z), q = a.x * a.y * p;
        const warpcheck::Vector3f t{1 + sign * a.x * a.x * p, sign * q, -sign * a.x}, b{q, sign + a.y * a.y * p, -a.y};
        const float omc = u.x * omc_max, st = std::sqrt(omc * (2 - omc)), phi = 2 * std::numbers::pi_v<float> * u.y;
        const float x = st * std::cos(phi), y = st * std::sin(phi), z = 1 - omc;
        return {{x * t.x + y * b.x + z * a.x, x * t.y + y * b.y + z * a.y, x * t.z + y * b.z + z * a.z},
                1 / (2 * std::numbers::pi_v<float> * omc_max), le, d - r};
    }
    float pdf(warpcheck::Vector3f ref, warpcheck::Vector3f wi) const {
        return hits(ref, wi) ? 1 / (2 * std::numbers::pi_v<float> * one_minus_cos_max(ref)) : 0.0f;
    }
    float L(warpcheck::Vector3f ref, warpcheck::Vector3f wi) const { return hits(ref, wi) ? le : 0.0f; }
    /// The bug of an MIS sum that mixes measures: the density per area of the
    /// sphere's silhouette disk, 1 / (pi r^2), where the sampler's is per solid angle.
    float pdf_per_area(warpcheck::Vector3f ref, warpcheck::Vector3f wi) const {
        return hits(ref, wi) ? 1 / (std::numbers::pi_v<float> * r * r) : 0.0f;
    }
};
