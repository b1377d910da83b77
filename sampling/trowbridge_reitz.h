// The Trowbridge-Reitz (GGX) microfacet distribution, isotropic and anisotropic,
// with two warps and their inverses:
//   - normals wm with density D(wm) cos(theta_m) (the projected-area distribution);
//   - visible normals for a view wo with density G1(wo) max(0, wo.wm) D(wm) / cos(theta_o)
//     (Heitz 2018), sampled with the spherical-caps method (Dupuy and Benyoub 2023).
// Directions are in the shading frame (z is the macrosurface normal); densities
// are with respect to the solid angle of wm; inputs u in [0,1)^2.
//
// Both warps rest on one fact: the distribution is the distribution of normals of
// the ellipsoid x^2 alpha_x^2 + y^2 alpha_y^2 + z^2 = 1 ("stretch" by
// (1/alpha_x, 1/alpha_y, 1) of the unit hemisphere). A normal n of the hemisphere
// maps to the ellipsoid normal normalize(alpha_x n.x, alpha_y n.y, n.z), a view w
// maps the other way, to normalize(alpha_x w.x, alpha_y w.y, w.z), and dot
// products between views and normals keep their sign. So each warp samples the
// unit hemisphere (where the answer is simple) and stretches the result.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sampling/disk.h"
#include "sampling/math.h"
#include "sampling/vector.h"

namespace warpcheck {

class TrowbridgeReitzNormals;
class TrowbridgeReitzVisibleNormals;
namespace lanes {
struct TrowbridgeReitzVisibleNormalsLanes;  // its vectorised twin (sampling/lane_warps.h)
}

/// The Trowbridge-Reitz distribution of microfacet normals with roughness
/// alpha_x, alpha_y (alpha is tan of the slope's standard scale; alpha_x = alpha_y
/// is isotropic).
class TrowbridgeReitz {
public:
    /// Roughness range. Below 1e-4 the typical 1 - cos(theta_m) ~ alpha^2 / 2 is
    /// under the float spacing of cos theta near 1 (6e-8): such a surface is a
    /// mirror to a float renderer and should be treated as specular. Above 1e4
    /// almost every normal lies within 1e-4 of the horizon.
    static constexpr float kMinAlpha = 1e-4f;
    static constexpr float kMaxAlpha = 1e4f;

    TrowbridgeReitz(float alpha_x, float alpha_y) : ax_(alpha_x), ay_(alpha_y) {
        check_alpha(alpha_x, "alpha_x");
        check_alpha(alpha_y, "alpha_y");
    }
    explicit TrowbridgeReitz(float alpha) : TrowbridgeReitz(alpha, alpha) {}

    float alpha_x() const { return ax_; }
    float alpha_y() const { return ay_; }

    /// D(wm): the microfacet normal density with respect to the solid angle of wm,
    /// normalised so that its integral against cos(theta_m) over the hemisphere is 1:
    ///   D = 1 / (pi ax ay (x^2/ax^2 + y^2/ay^2 + z^2)^2)
    /// (the familiar 1/(pi ax ay cos^4 (1 + tan^2 (cos^2 phi/ax^2 + sin^2 phi/ay^2))^2)
    /// multiplied out; no tan, so it is finite at the horizon). 0 for wm.z < 0.
    float D(Vector3f wm) const {
        if (wm.z < 0.0f) return 0.0f;
        const float sx = wm.x / ax_, sy = wm.y / ay_;
        const float s = sx * sx + sy * sy + wm.z * wm.z;
        return 1.0f / (kPi * ax_ * ay_ * s * s);
    }

    /// Smith's Lambda(w) = (sqrt(1 + alpha^2 tan^2 theta) - 1) / 2 with
    /// alpha^2 tan^2 theta = (ax^2 x^2 + ay^2 y^2) / z^2, written as
    /// q / (2 |z| (|z| + sqrt(z^2 + q))), q = ax^2 x^2 + ay^2 y^2, to avoid the
    /// cancellation near normal incidence. +inf at the horizon. Symmetric in z.
    float lambda(Vector3f w) const {
        const float z = std::abs(w.z), q = slope_term(w);
        return q / (2.0f * z * (z + std::sqrt(z * z + q)));
    }

    /// Smith's masking G1(w) = 1 / (1 + Lambda(w)) = 2 |z| / (|z| + sqrt(z^2 + q)):
    /// 1 at normal incidence, 0 at the horizon. Symmetric in z.
    float G1(Vector3f w) const {
        const float z = std::abs(w.z);
        return 2.0f * z / (z + std::sqrt(z * z + slope_term(w)));
    }

    /// G1(w) / |cos theta| = 2 / (|z| + sqrt(z^2 + q)): finite even at the horizon,
    /// where both factors vanish. The visible-normal density uses this ratio.
    float G1_over_cos(Vector3f w) const {
        const float z = std::abs(w.z);
        return 2.0f / (z + std::sqrt(z * z + slope_term(w)));
    }

    // --- Normals with density D(wm) cos(theta_m) --------------------------------

    /// The warp for normals with density D(wm) cos(theta_m); see TrowbridgeReitzNormals.
    TrowbridgeReitzNormals normals() const;

    /// The marginal density of cos(theta_m) under TrowbridgeReitzNormals::sample, isotropic case
    /// (alpha = alpha_x): p(z) = 2 pi z D(z) = 2 alpha^2 z / (1 + (alpha^2 - 1) z^2)^2
    /// on [0, 1]. In double: it is a reference for tests and checks.
    static double isotropic_cos_theta_pdf(double alpha, double z) {
        const double a2 = alpha * alpha, den = 1.0 + (a2 - 1.0) * z * z;
        return z >= 0.0 && z <= 1.0 ? 2.0 * a2 * z / (den * den) : 0.0;
    }

    /// The marginal density of the azimuth phi_m in [0, 2 pi) under TrowbridgeReitzNormals::sample:
    /// tan(phi_m) = (ay/ax) tan(2 pi u.y), so
    ///   p(phi) = ax ay / (2 pi (ay^2 cos^2 phi + ax^2 sin^2 phi)).
    static double azimuth_pdf(double ax, double ay, double phi) {
        const double c = std::cos(phi), s = std::sin(phi);
        return ax * ay / (2.0 * std::numbers::pi * (ay * ay * c * c + ax * ax * s * s));
    }

    // --- Visible normals ----------------------------------------------------------

    /// The warp for visible normals seen from wo; see TrowbridgeReitzVisibleNormals.
    TrowbridgeReitzVisibleNormals visible_normals(Vector3f wo) const;

private:
    static void check_alpha(float a, const char* name) {
        if (!(a >= kMinAlpha && a <= kMaxAlpha))
            throw std::invalid_argument(std::string("trowbridge_reitz: ") + name + " must be in [1e-4, 1e4], got " +
                                        std::to_string(a));
    }
    /// alpha^2 tan^2(theta) |z|^2 = ax^2 x^2 + ay^2 y^2.
    float slope_term(Vector3f w) const {
        const float x = ax_ * w.x, y = ay_ * w.y;
        return x * x + y * y;
    }

    float ax_, ay_;
};

/// Trowbridge-Reitz microfacet normals wm with density D(wm) cos(theta_m), the
/// projected-area distribution, with respect to the solid angle of wm.
class TrowbridgeReitzNormals {
public:
    explicit TrowbridgeReitzNormals(const TrowbridgeReitz& distribution) : tr_(distribution) {}

    const TrowbridgeReitz& distribution() const { return tr_; }

    /// Samples wm with density D(wm) cos(theta_m). On the unit hemisphere the
    /// projected-area distribution of normals is uniform on the disk below it, so
    /// take a uniform disk point p (polar map: r^2 = u.x, phi = 2 pi u.y), lift it
    /// to n = (p, sqrt(1 - r^2)) and stretch: wm = normalize(ax p.x, ay p.y, sqrt(1 - u.x)).
    /// Isotropic: tan^2 theta_m = alpha^2 u.x / (1 - u.x). cos(theta_m) depends on
    /// u.x only (decreasing) when isotropic; the azimuth depends on u.y only
    /// (increasing) always.
    Vector3f sample(Point2f u) const {
        const Point2f p = UniformDiskPolar{}.sample(u);
        return normalize({tr_.alpha_x() * p.x, tr_.alpha_y() * p.y, safe_sqrt(1.0f - u.x)});
    }

    /// Density of sample with respect to solid angle: D(wm) cos(theta_m), 0 below the horizon.
    float pdf(Vector3f wm) const { return wm.z > 0.0f ? tr_.D(wm) * wm.z : 0.0f; }

    /// Inverse of sample: unstretch to n ~ (wm.x/ax, wm.y/ay, wm.z); then
    /// u.x = r^2 = |n.xy|^2 / |n|^2 and u.y is the azimuth of n.
    Point2f invert(Vector3f wm) const {
        const float nx = wm.x / tr_.alpha_x(), ny = wm.y / tr_.alpha_y(), nz = std::max(wm.z, 0.0f);
        const float rho2 = nx * nx + ny * ny;
        return {std::min(rho2 / (rho2 + nz * nz), kOneMinusEpsilon), azimuth_to_unit(nx, ny)};
    }

private:
    TrowbridgeReitz tr_;
};

/// Visible normals of a Trowbridge-Reitz surface seen from the direction wo:
/// density with respect to the solid angle of wm (on the hemisphere z >= 0)
///     D_wo(wm) = G1(wo) max(0, wo.wm) D(wm) / cos(theta_o),
/// which integrates to 1 over the hemisphere for every wo. Without the max (with
/// |wo.wm| instead) it does not: back-facing normals would add mass.
///
/// Method (spherical caps, Dupuy and Benyoub 2023). In the unstretched
/// configuration the surface is the unit hemisphere and the view is
/// wi = normalize(ax wo.x, ay wo.y, wo.z). The visible normal for wi is the half
/// vector normalize(c + wi) of wi and a point c uniform on the spherical cap
/// z >= -wi.z (the reflection of wi about a visible normal is uniform there).
/// Here c comes from a uniform disk point d (concentric map) through the
/// equal-area map of the disk onto the cap, 1 - z = r^2 (1 + wi.z):
///     c = (d sqrt(k (1 + z)), z),   k = 1 + wi.z,   r = |d|,
/// and 1 - r^2 is taken from u exactly, so normals near the horizon keep their
/// precision. Every step is invertible: c = 2 (wi.h) h - wi recovers the cap
/// point from the unstretched normal h, then d, then u.
///
/// Defined behaviour at the edges:
/// - wo below the horizon (wo.z < 0) is replaced by -wo: a ray arriving from
///   inside sees the microsurface from the other side (the usual convention for
///   transmission). wo is normalised; a zero or non-finite wo throws.
/// - Grazing wo (wo.z = 0) is fine: G1(wo)/cos(theta_o) is evaluated as one
///   finite ratio, and the cap becomes the upper hemisphere.
/// - The map has one singular point, c = -wi, where the whole semicircle of
///   normals perpendicular to wo collapses to one input. The disk is rotated so
///   that this point is the concentric image of u = (1, 0.75): outside the
///   half-open square [0,1)^2, and away from the square's edge midpoints and
///   corners. (Within ~1e-7 of it, float rounding can leave wo.wm <= 0 and so a
///   zero pdf: a set of inputs of measure ~1e-14.) At normal incidence there is
///   no singular point; inputs on the square's boundary with r = 1 map to
///   horizon normals, where the density is 0.
/// - At alpha = 1e-4 (the smallest accepted) every step stays in range: the
///   stretch only rescales x and y by alpha, and the density peaks at 1/(pi ax ay) = 3.2e7.
class TrowbridgeReitzVisibleNormals {
public:
    TrowbridgeReitzVisibleNormals(const TrowbridgeReitz& distribution, Vector3f wo) : tr_(distribution) {
        const float len = length(wo);
        if (!(len > 0.0f) || !std::isfinite(len))
            throw std::invalid_argument("trowbridge_reitz_visible: wo must be a finite, non-zero direction");
        wo_ = (1.0f / len) * wo;
        if (wo_.z < 0.0f) wo_ = -1.0f * wo_;
        wi_ = normalize({tr_.alpha_x() * wo_.x, tr_.alpha_y() * wo_.y, wo_.z});
        k_ = 1.0f + wi_.z;
        // |wi.xy|^2 / k = (1 - wi.z^2) / (1 + wi.z) = 1 - wi.z, without the cancellation of 1 - wi.z.
        const double w = std::hypot(static_cast<double>(wi_.x), static_cast<double>(wi_.y));
        one_minus_wi_z_ = w * w / k_;
        normal_incidence_ = w == 0.0;
        // Rotation of the disk: disk angle pi/8 (the rim point of u = (1, 0.75))
        // goes to the azimuth of -wi, i.e. rotate by phi_i + 7 pi / 8.
        const double ex = normal_incidence_ ? 1.0 : wi_.x / w, ey = normal_incidence_ ? 0.0 : wi_.y / w;
        rotation_ = std::atan2(ey, ex) + 7.0 * std::numbers::pi / 8.0;
        rot_cos_ = static_cast<float>(std::cos(rotation_));
        rot_sin_ = static_cast<float>(std::sin(rotation_));
        g1_over_cos_o_ = tr_.G1_over_cos(wo_);
    }

    const TrowbridgeReitz& distribution() const { return tr_; }
    /// The view actually used: normalised, and flipped to z >= 0.
    Vector3f wo() const { return wo_; }

    /// Samples a visible normal wm (z >= 0) with density pdf(wm).
    ///
    /// Computed in double, rounded to float at the end, because of one
    /// cancellation: near the singular point the half vector h = c + wi is a small
    /// difference of unit-length terms, and wo.wm is second order in |h|. In float
    /// (concentric map included, whose cos/sin carry the error) wo.wm lost ~10% of
    /// its digits within 1e-3 of that point, which the inverse then turned into
    /// round-trip errors of 5e-5 in u. In double the only float error is the final
    /// rounding of wm, which the inverse maps back to ~1e-7 in u.
    Vector3f sample(Point2f u) const {
        // The concentric map in double: (a, b) = 2u - 1 are exact, and so is 1 - r.
        const double a = 2.0 * static_cast<double>(u.x) - 1.0, b = 2.0 * static_cast<double>(u.y) - 1.0;
        double r = 0.0, phi = 0.0;
        if (std::abs(a) > std::abs(b)) {
            r = a;
            phi = std::numbers::pi / 4.0 * (b / a);
        } else if (b != 0.0) {
            r = b;
            phi = std::numbers::pi / 2.0 - std::numbers::pi / 4.0 * (a / b);
        }
        const double one_minus_r = 1.0 - std::abs(r);
        const double one_minus_r2 = one_minus_r * (2.0 - one_minus_r);  // 1 - r^2 = (1 - r)(1 + r), exact from u
        const SinCosDouble sc = sin_cos_double(phi + rotation_);  // |phi + rotation_| < 8.3
        const double dx = r * sc.cos, dy = r * sc.sin;
        double hx, hy, hz;
        if (normal_incidence_) {
            // k = 2 and 1 + z = 2 (1 - r^2): h = c + wi = 2 sqrt(1 - r^2) (d, sqrt(1 - r^2)),
            // the cosine-weighted hemisphere (visible normals at normal incidence are D cos).
            hx = dx;
            hy = dy;
            hz = std::sqrt(one_minus_r2);
        } else {
            // sin(theta_c) / r = sqrt(k (1 + z)) with 1 + z = (1 - wi.z) + k (1 - r^2):
            // two non-negative terms, no cancellation.
            const double k = k_;
            const double scale = std::sqrt(k * (one_minus_wi_z_ + k * one_minus_r2));
            hx = dx * scale + wi_.x;
            hy = dy * scale + wi_.y;
            hz = k * one_minus_r2;
            if (hx == 0.0 && hy == 0.0 && hz == 0.0) {  // c = -wi: not reachable from u in [0,1)^2
                hx = -wi_.y;
                hy = wi_.x;
            }
        }
        const double mx = tr_.alpha_x() * hx, my = tr_.alpha_y() * hy;
        const double inv_len = 1.0 / std::sqrt(mx * mx + my * my + hz * hz);
        return {static_cast<float>(mx * inv_len), static_cast<float>(my * inv_len), static_cast<float>(hz * inv_len)};
    }

    /// Density with respect to the solid angle of wm: G1(wo) max(0, wo.wm) D(wm) / cos(theta_o)
    /// for wm.z >= 0, else 0.
    float pdf(Vector3f wm) const {
        if (wm.z < 0.0f) return 0.0f;
        return g1_over_cos_o_ * std::max(dot(wo_, wm), 0.0f) * tr_.D(wm);
    }

    /// Inverse of sample: the unstretched normal h, the cap point c = 2 (wi.h) h - wi,
    /// the disk point d, then the concentric map's inverse. For a normal that is not
    /// visible from wo the result is a valid input without meaning.
    Point2f invert(Vector3f wm) const {
        const Vector3f h = normalize({wm.x / tr_.alpha_x(), wm.y / tr_.alpha_y(), std::max(wm.z, 0.0f)});
        Point2f d;
        if (normal_incidence_) {
            d = {h.x, h.y};  // c = 2 h.z h - z, so d = c.xy / sqrt(2 (1 + c.z)) = h.xy
        } else {
            const float dot_ih = dot(wi_, h);
            const Vector3f c = (2.0f * dot_ih) * h - wi_;
            if (c.z >= 0.0f) {
                // d = c.xy / (sinθ_c / r) with sinθ_c / r = sqrt(k (1 + z)): 1 + z >= 1, accurate.
                const float inv = 1.0f / std::sqrt(k_ * (1.0f + c.z));
                d = {c.x * inv, c.y * inv};
            } else {
                // Lower part of the cap: r = sqrt((1 - z) / k) with 1 - z > 1, accurate;
                // the direction of d is that of c.xy.
                const float r = std::sqrt(std::min((1.0f - c.z) / k_, 1.0f));
                const float n = std::hypot(c.x, c.y);
                d = n > 0.0f ? Point2f{c.x * (r / n), c.y * (r / n)} : Point2f{r, 0.0f};
            }
        }
        return UniformDiskConcentric{}.invert(rotate(d, rot_cos_, -rot_sin_));
    }

private:
    friend struct lanes::TrowbridgeReitzVisibleNormalsLanes;
    static Point2f rotate(Point2f p, float c, float s) { return {c * p.x - s * p.y, s * p.x + c * p.y}; }

    TrowbridgeReitz tr_;
    Vector3f wo_;
    Vector3f wi_;               // wo in the unstretched configuration
    float k_ = 2.0f;            // 1 + wi.z
    double one_minus_wi_z_ = 0;  // 1 - wi.z
    bool normal_incidence_ = true;
    double rotation_ = 0.0;      // the disk's rotation: disk angle pi/8 -> azimuth of -wi
    float rot_cos_ = 1.0f, rot_sin_ = 0.0f;
    float g1_over_cos_o_ = 1.0f;
};

inline TrowbridgeReitzNormals TrowbridgeReitz::normals() const { return TrowbridgeReitzNormals(*this); }

/// Memoised per thread by (alpha_x, alpha_y, wo), bit for bit: a BSDF's
/// sampler builds the warp for every sample, and a check draws millions from
/// one wo (the constructor's atan2, cos and sin cost more than a sample).
inline TrowbridgeReitzVisibleNormals TrowbridgeReitz::visible_normals(Vector3f wo) const {
    return detail::memo_view<TrowbridgeReitzVisibleNormals>(std::array<float, 5>{ax_, ay_, wo.x, wo.y, wo.z},
                                                            [&] { return TrowbridgeReitzVisibleNormals(*this, wo); });
}

}  // namespace warpcheck
