// Correct warps whose round trips are limited by float resolution (issue 22,
// class 6), each with wrong twins of the same hardness. The math is written
// out here, as a renderer would write it, so a warp stays what it says
// whatever the library's warps become.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "validate/api/warp_case.h"

namespace warpcheck::testing::hard {

inline constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
inline constexpr float kBelowOne = 0x1.fffffep-1f;

inline float azimuth(float x, float y) {
    const float phi = std::atan2(y, x) / kTwoPi;
    return phi < 0.0f ? std::fmin(phi + 1.0f, kBelowOne) : phi;
}

/// Uniform in the triangle (0,0), (1,0), (0,1): x = 1 - sqrt(u.x), y = u.y
/// sqrt(u.x), with the inverse that is exact in real arithmetic. Near the
/// vertex (1,0) (u.x -> 0) x is rounded to a float of 1 - sqrt(u.x), and u.y =
/// y / (1 - x) inherits that rounding, amplified by 1 / sqrt(u.x). The wrong
/// twin adds `offset` to u.y where 1 - x < `near` (near the vertex only, or
/// everywhere for near = 1). `tolerance`: the case's round-trip tolerance (a
/// warp without trigonometry may state one tighter than the default 2^-16).
inline std::unique_ptr<WarpCase> triangle(const std::string& name, float offset = 0.0f, float near = 1.0f,
                                          double tolerance = 0x1p-16) {
    WarpCaseInfo info{name, {}, "uniform triangle by sqrt", InputKind::Uniform2D, chi2::Domain::unit_square()};
    info.roundtrip_tolerance = tolerance;
    return make_warp_case(
        info,
        warp_of([](Point2f u) {
                    const float s = std::sqrt(u.x);
                    return Point2f{1.0f - s, u.y * s};
                })
            .with_pdf([](Point2f p) { return p.x >= 0.0f && p.y >= 0.0f && p.x + p.y <= 1.0f ? 2.0f : 0.0f; })
            .with_invert([offset, near](Point2f p) {
                             const float s = 1.0f - p.x;
                             float v = s > 0.0f ? p.y / s : 0.0f;
                             if (s < near) v += offset;
                             return Point2f{s * s, std::clamp(v, 0.0f, kBelowOne)};
                         }));
}

/// The Phong lobe cos^n theta on the hemisphere: cos theta = u.x^(1/(n+1)),
/// phi = 2 pi u.y, with the renderer's inverse u.x = cos theta^(n+1), clamped
/// below 1. Near the peak a float step of cos theta is (n+1) 2^-24 of u.x (6e-4
/// for n = 10^4), and every u.x whose cos theta rounds to 1 maps to the pole.
/// The wrong twin raises cos theta to (n+1) * `exponent_scale` (the inverse of
/// a neighbouring lobe), or to n for `off_by_one`.
inline std::unique_ptr<WarpCase> phong(const std::string& name, float n, float exponent_scale = 1.0f,
                                       bool off_by_one = false) {
    WarpCaseInfo info{name, {{"n", n}}, "Phong lobe cos^n", InputKind::Uniform2D, chi2::Domain::hemisphere()};
    const float exponent = off_by_one ? n : (n + 1.0f) * exponent_scale;
    return make_warp_case(
        info,
        warp_of([n](Point2f u) {
            const float z = std::pow(u.x, 1.0f / (n + 1.0f));
            const float r = std::sqrt(std::fmax(0.0f, 1.0f - z * z)), phi = kTwoPi * u.y;
            return Vector3f{r * std::cos(phi), r * std::sin(phi), z};
        })
            .with_pdf([n](Vector3f w) { return w.z >= 0.0f ? (n + 1.0f) / kTwoPi * std::pow(w.z, n) : 0.0f; })
            .with_invert([exponent](Vector3f w) { return Point2f{std::fmin(std::pow(w.z, exponent), kBelowOne), azimuth(w.x, w.y)}; }));
}

/// A uniform cone (a sun) of half-angle `degrees` on its own cap, as one-minus-
/// cos samplers write it: 1 - cos theta = u.x (1 - cos_max), sin theta from
/// (1 - cos)(2 - (1 - cos)), with the inverse u.x = (1 - z) / (1 - cos_max).
/// At 0.25 degree z takes only 160 floats over the whole of u.x (a float step
/// of z is 6e-3 of u.x), so the inverse reads u.x back within a step of z. The
/// wrong twin's inverse scales u.x by `inverse_scale`.
inline std::unique_ptr<WarpCase> tiny_cone(const std::string& name, float degrees, float inverse_scale = 1.0f) {
    const float cos_max = std::cos(degrees * std::numbers::pi_v<float> / 180.0f);
    WarpCaseInfo info{name, {{"half_angle_deg", degrees}}, "uniform cone", InputKind::Uniform2D,
                      chi2::Domain::spherical_cap(cos_max)};
    return make_warp_case(
        info,
        warp_of([cos_max](Point2f u) {
            const float one_minus_cos = u.x * (1.0f - cos_max), phi = kTwoPi * u.y;
            const float r = std::sqrt(one_minus_cos * (2.0f - one_minus_cos));
            return Vector3f{r * std::cos(phi), r * std::sin(phi), 1.0f - one_minus_cos};
        })
            .with_pdf([cos_max](Vector3f w) { return w.z >= cos_max ? 1.0f / (kTwoPi * (1.0f - cos_max)) : 0.0f; })
            .with_invert([cos_max, inverse_scale](Vector3f w) {
                return Point2f{std::fmin(inverse_scale * (1.0f - w.z) / (1.0f - cos_max), kBelowOne), azimuth(w.x, w.y)};
            }));
}

/// Uniform on [0, a] as x = a u, inverted by multiplying with the reciprocal,
/// x * (1 / a), as renderers write it: for a = 7 the largest float below 1
/// comes back as exactly 1.0. The wrong twin returns 1.0 for every u >= `from`.
inline std::unique_ptr<WarpCase> scaled_interval(const std::string& name, float a, float from = 2.0f) {
    WarpCaseInfo info{name, {{"a", a}}, "uniform on [0, a]", InputKind::Uniform1D, chi2::Domain::interval(0.0, a)};
    return make_warp_case(
        info, warp_of([a](float u) { return a * u; })
                  .with_pdf([a](float x) { return x >= 0.0f && x <= a ? 1.0f / a : 0.0f; })
                  .with_invert([a, from](float x) {
                                   const float u = x * (1.0f / a);
                                   return u >= from ? 1.0f : u;
                               }));
}

/// The same in 2D: uniform on the rectangle [0, a] x [0, 1] (a light of width
/// a), inverted by multiplying with the reciprocal width. The wrong twin
/// returns 1.0 for u.x for every u.x >= `from`.
inline std::unique_ptr<WarpCase> scaled_rectangle(const std::string& name, float a, float from = 2.0f) {
    WarpCaseInfo info{name, {{"a", a}}, "uniform on [0, a] x [0, 1]", InputKind::Uniform2D,
                      chi2::Domain::box(0.0, a, 0.0, 1.0)};
    return make_warp_case(
        info,
            warp_of([a](Point2f u) { return Point2f{a * u.x, u.y}; })
                .with_pdf([a](Point2f p) { return p.x >= 0.0f && p.x <= a && p.y >= 0.0f && p.y <= 1.0f ? 1.0f / a : 0.0f; })
                .with_invert([a, from](Point2f p) {
                    const float u = p.x * (1.0f / a);
                    return Point2f{u >= from ? 1.0f : u, p.y};
                }));
}

}  // namespace warpcheck::testing::hard
