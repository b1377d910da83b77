// Correct float warps that are hard for the statistics, and their wrong twins
// of the same hardness, written as a renderer writes them (float arithmetic,
// the textbook formulas), not taken from sampling/. The chi-square tests of
// tests/validate/checks/chi2/test_chi2_float.cpp run them.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "sampling/vector.h"
#include "validate/api/warp_case.h"

namespace warpcheck::testing::hard {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kInv4Pi = 0.25f * std::numbers::inv_pi_v<float>;

inline Vector3f normalized(Vector3f v) {
    const float len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    return {v.x / len, v.y / len, v.z / len};
}

/// An orthonormal frame around a unit vector n (Duff et al. 2017).
struct Frame {
    Vector3f s, t, n;
    explicit Frame(Vector3f axis) : n(axis) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sign + n.z), b = n.x * n.y * a;
        s = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
        t = {b, sign + n.y * n.y * a, -n.y};
    }
    Vector3f from_local(float x, float y, float z) const {
        return {x * s.x + y * t.x + z * n.x, x * s.y + y * t.y + z * n.y, x * s.z + y * t.z + z * n.z};
    }
};

/// Henyey-Greenstein about the direction `forward`, in the textbook float
/// form: the density's denominator 1 + g^2 - 2 g cos is rounded before it
/// cancels, so the float pdf integrates to 1 only to ~1e-5 (g = 0.95) or
/// ~1e-4 (g = 0.99). `scale` multiplies the density (the wrong twin's 1 + 1e-3).
struct HenyeyGreenstein {
    float g;
    Vector3f forward{0.0f, 0.0f, 1.0f};
    float scale = 1.0f;

    /// By inversion of the CDF, t = 1 - cos theta formed without cancellation
    /// and sin theta from it (from the float cos theta, the samples would lie
    /// on rings about the axis with 3e-4 of them exactly on it at g = 0.99:
    /// a flaw the chi-square cells of equal probability see, issue 34).
    Vector3f sample(Point2f u) const {
        const float q = 1.0f - g + 2.0f * g * u.x, s = (1.0f - g * g) / q;
        const float t = std::min((1.0f - g) * (1.0f - u.x) * (s + 1.0f - g) / q, 2.0f);
        const float sin_theta = std::sqrt(std::max(0.0f, t * (2.0f - t)));
        const float phi = 2.0f * kPi * u.y;
        return Frame(forward).from_local(sin_theta * std::cos(phi), sin_theta * std::sin(phi), 1.0f - t);
    }
    float pdf(Vector3f w) const {
        const float c = forward.x * w.x + forward.y * w.y + forward.z * w.z;
        const float denom = 1.0f + g * g - 2.0f * g * c;
        return scale * kInv4Pi * (1.0f - g * g) / (denom * std::sqrt(denom));
    }
};

inline std::unique_ptr<WarpCase> henyey_greenstein(const std::string& family, float g, Vector3f forward,
                                                   float scale = 1.0f) {
    return make_warp_case({.family = family,
                           .params = {{"g", g}, {"forward_z", forward.z}, {"scale", scale}},
                           .description = "Henyey-Greenstein phase function, textbook float formula",
                           .domain = chi2::Domain::sphere()},
                          HenyeyGreenstein{g, forward, scale});
}

/// Uniform directions in a cone of half-angle `degrees` about +z: 1 - cos =
/// u (1 - cos_max), sin theta from it, so that x and y keep their resolution:
/// a tiny cap ("a sun") has only a few hundred float values of cos theta.
/// (pbrt's cos = (1 - u) + u cos_max with sin from the float cos puts its
/// samples on as many rings, half a ring's mass exactly on the axis: a flaw
/// now seen, issue 34.)
struct SunCone {
    float cos_max;
    float sampled_one_minus = 0.0f;  ///< 1 - cos of the sampled cap (0: the claimed one)
    float azimuth_turn = 1.0f;       ///< the share of the turn the azimuth covers (the twin's 0.98)

    Vector3f sample(Point2f u) const {
        const float one_minus = sampled_one_minus > 0.0f ? sampled_one_minus : 1.0f - cos_max;
        const float t = u.x * one_minus;
        const float sin_theta = std::sqrt(std::max(0.0f, t * (2.0f - t)));
        const float phi = 2.0f * kPi * azimuth_turn * u.y;
        return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), 1.0f - t};
    }
    float pdf(Vector3f w) const { return w.z >= cos_max ? 1.0f / (2.0f * kPi * (1.0f - cos_max)) : 0.0f; }
};

/// Uniform on the triangle x, y >= 0, x + y <= 1 inside the unit square (the
/// square as domain, density 2 on the triangle): the jump along x + y = 1 runs
/// through the chi-square cells' corners, where Gauss-Kronrod's symmetric
/// nodes sit exactly on it. `density` is the twin's wrong constant.
struct SquareTriangle {
    float density = 2.0f;
    Point2f sample(Point2f u) const {
        if (u.x + u.y > 1.0f) return {1.0f - u.x, 1.0f - u.y};
        return u;
    }
    float pdf(Point2f p) const { return p.x >= 0.0f && p.y >= 0.0f && p.x + p.y <= 1.0f ? density : 0.0f; }
};

/// The Phong lobe cos^n about +z: z = u^(1/(n+1)); `pdf_exponent` is the
/// twin's wrong exponent in the density.
struct PhongLobe {
    float n;
    float pdf_exponent;
    Vector3f sample(Point2f u) const {
        const float z = std::pow(u.x, 1.0f / (n + 1.0f));
        const float r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * u.y;
        return {r * std::cos(phi), r * std::sin(phi), z};
    }
    float pdf(Vector3f w) const {
        return w.z <= 0.0f ? 0.0f : (pdf_exponent + 1.0f) / (2.0f * kPi) * std::pow(w.z, pdf_exponent);
    }
};

/// A rectangle light [-a, a] x [-b, b] on the plane z = 1 above the origin,
/// sampled by area and converted to solid angle: pdf = dist^2 / (area cos) =
/// 1 / (4 a b z^3) inside its silhouette, 0 outside (a jump). `sample_b` is the
/// sampled half-height (the twin samples a wider light than its pdf claims);
/// `cos_power` is 3 (the twin forgets the cosine: 2).
struct RectangleLight {
    float a, b;
    float sample_b = 0.0f;
    float cos_power = 3.0f;
    Vector3f sample(Point2f u) const {
        const float hb = sample_b > 0.0f ? sample_b : b;
        const float x = a * (2.0f * u.x - 1.0f), y = hb * (2.0f * u.y - 1.0f);
        return normalized({x, y, 1.0f});
    }
    float pdf(Vector3f w) const {
        if (w.z <= 0.0f || std::abs(w.x) > a * w.z || std::abs(w.y) > b * w.z) return 0.0f;
        return 1.0f / (4.0f * a * b * std::pow(w.z, cos_power));
    }
};

}  // namespace warpcheck::testing::hard
