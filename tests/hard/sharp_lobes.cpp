// Issue 34: sharp lobes registered without an inverse (as renderers ship
// them), and the next classes of correct-but-hard warps. Each correct warp
// beside a wrong twin of the same hardness, which a distribution check (chi2
// or unbinned) must catch: none of them has an inverse for roundtrip to
// catch it with.
//
// Sharp lobes on the sphere:
// - vmf[kappa=1e6]: a von Mises-Fisher lobe about +z, sampled stably (Jakob
//   2012): 1 - cos theta = -log(u) / kappa in float, sin theta from it, so
//   that x and y keep their float resolution; pdf kappa / (2 pi) exp(-kappa
//   t), t = 1 - cos theta from x and y. Hard: the lobe is 1e-6 sr, a few
//   dozen float values of cos theta; quadrature nodes step over it. Twin:
//   sin theta from the float cos theta (a real and common bug): every sample
//   on one of a few hundred rings, 3% exactly at the pole.
// - beckmann[alpha=0.05, 0.01]: Beckmann normals with density D cos theta,
//   tan^2 theta = -alpha^2 log(1 - u). Hard: a 32 x 32 grid in (phi, cos
//   theta) has the whole lobe in its top row and tests only the azimuth.
//   Twins: sampled with alpha 2% too large.
// - ggx_visible[alpha=0.001]: the built-in Trowbridge-Reitz visible normals
//   at alpha 1e-3 seen from theta_o = 60. Twin: sampled with alpha 2% too large.
// Small supports:
// - disk_light_oblique: a disk light of radius 0.042 at distance 1, its
//   normal 85 degrees from the direction to it (4.8e-4 sr), sampled by area
//   and converted to solid angle. Twin: dist^2 taken at the light's centre.
// Supports thin in one direction:
// - annulus[width=1e-4]: uniform on the ring 0.5 <= r <= 0.5001 of the unit
//   disk. Hard: samples on its edges round across them (pdf 0), in
//   proportion to its boundary's length, not to its area. Twin: sampled 1%
//   too wide (outside the support the pdf describes).
// Densities infinite at an end of the domain:
// - power_end[a=0.1]: 0.1 x^-0.9 on [0, 1] (x = u^10); arcsine on [0, 1]
//   (x = sin^2(pi u / 2)); weibull[k=0.5] on [0, inf). Hard: the density is
//   unbounded at 0; quadrature and tables that do not substitute around the
//   end miss mass there (4e-3 of it in a 65,536-bucket table's first bucket
//   for the power law). Twins: the power law sampled as u^10.2; the Weibull
//   sampled with k 2% too small.
#include <cmath>
#include <limits>
#include <string>

#include <sampling/trowbridge_reitz.h>

#include "hard_warps.h"

namespace hard {
namespace {

using warpcheck::chi2::Domain;
using warpcheck::cross;
using warpcheck::dot;
using warpcheck::normalize;

// --- von Mises-Fisher about +z ------------------------------------------------

struct VonMisesFisher {
    float kappa;
    bool rings = false;  // twin: sin theta from the float cos theta

    Vector3f sample(Point2f u) const {
        // 1 - cos theta = -log(u + (1 - u) exp(-2 kappa)) / kappa; exp(-2 kappa)
        // is 0 in float for kappa > 52, so u.x is kept from 0 (which would go
        // to the antipode, where the float density is 0), as renderers keep
        // their inputs in (0, 1).
        const float v = std::fmin(-std::log(std::fmax(u.x, 0x1p-149f)) / kappa, 2.0f);
        const float phi = 2 * kPi * u.y;
        if (rings) {
            const float cos_theta = 1 - v;
            return spherical_direction(cos_theta, phi);
        }
        const float sin_theta = std::sqrt(std::fmax(0.0f, v * (2 - v)));
        return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), 1 - v};
    }
    /// kappa / (2 pi (1 - exp(-2 kappa))) exp(-kappa (1 - cos theta)), with
    /// 1 - cos theta = (x^2 + y^2) / (1 + z) on the upper hemisphere, the
    /// constant inside the exponential so that the density does not underflow
    /// before the product does (u.x = 2^-149 reaches kappa t = 103).
    float pdf(Vector3f w) const {
        const float t = w.z > 0 ? (w.x * w.x + w.y * w.y) / (1 + w.z) : 1 - w.z;
        return std::exp(std::log(kappa / (2 * kPi)) - kappa * t);
    }
};

void add_vmf(warpcheck::Registry& registry, const std::string& family, VonMisesFisher lobe) {
    registry.add_case(warpcheck::make_warp_case({.family = family,
                                                 .params = {{"kappa", lobe.kappa}},
                                                 .description = "von Mises-Fisher lobe about +z, no inverse",
                                                 .domain = Domain::sphere()},
                                                lobe));
}

// --- Beckmann normals -----------------------------------------------------------

struct BeckmannNormals {
    float alpha;
    float sampled_alpha = alpha;  // twin: sampled with another width

    Vector3f sample(Point2f u) const {
        const float tan_theta = sampled_alpha * std::sqrt(-std::log1p(-u.x));
        const float phi = 2 * kPi * u.y;
        return normalize({tan_theta * std::cos(phi), tan_theta * std::sin(phi), 1});
    }
    /// D(wm) cos theta = exp(-tan^2 / alpha^2) / (pi alpha^2 cos^3), tan^2 from x and y.
    float pdf(Vector3f w) const {
        if (w.z <= 0) return 0;
        const float tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z);
        return std::exp(-tan2 / (alpha * alpha)) / (kPi * alpha * alpha * w.z * w.z * w.z);
    }
};

void add_beckmann(warpcheck::Registry& registry, const std::string& family, BeckmannNormals lobe) {
    registry.add_case(warpcheck::make_warp_case({.family = family,
                                                 .params = {{"alpha", lobe.alpha}},
                                                 .description = "Beckmann normals, density D cos theta, no inverse",
                                                 .domain = Domain::hemisphere()},
                                                lobe));
}

// --- Trowbridge-Reitz visible normals at a tiny roughness ----------------------

struct GgxVisible {
    warpcheck::TrowbridgeReitzVisibleNormals claimed, sampled;
    Vector3f sample(Point2f u) const { return sampled.sample(u); }
    float pdf(Vector3f w) const { return claimed.pdf(w); }
};

GgxVisible ggx_visible(float alpha, float sampled_alpha, float theta_o_deg) {
    const Vector3f wo = unit_vector_deg(theta_o_deg, 0);
    return {warpcheck::TrowbridgeReitz(alpha).visible_normals(wo),
            warpcheck::TrowbridgeReitz(sampled_alpha).visible_normals(wo)};
}

void add_ggx_visible(warpcheck::Registry& registry, const std::string& family, float alpha, GgxVisible lobe) {
    registry.add_case(warpcheck::make_warp_case(
        {.family = family,
         .params = {{"alpha", alpha}, {"theta_o", 60}},
         .description = "Trowbridge-Reitz visible normals at a tiny roughness, no inverse",
         .domain = Domain::hemisphere()},
        lobe));
}

// --- A small disk light seen obliquely -----------------------------------------

struct ObliqueDiskLight {
    Vector3f centre = unit_vector_deg(50, 20);  // at distance 1
    Frame frame = light_frame();
    float radius = 0.042f;
    bool distance_at_centre = false;  // twin: dist^2 of the centre, not of the point

    /// The light's normal 85 degrees from -centre, rotated about the
    /// perpendicular of centre and +z.
    static Frame light_frame() {
        const Vector3f c = unit_vector_deg(50, 20);
        const Vector3f side = normalize(cross(c, {0, 0, 1}));
        const float a = 85 * kPi / 180;
        return Frame::from_z(normalize(std::cos(a) * (-1.0f * c) + std::sin(a) * side));
    }
    float area() const { return kPi * radius * radius; }
    Vector3f sample(Point2f u) const {
        const float r = radius * std::sqrt(u.x), phi = 2 * kPi * u.y;
        const Vector3f p = centre + (r * std::cos(phi)) * frame.x + (r * std::sin(phi)) * frame.y;
        return normalize(p);
    }
    /// The ray from the origin along w meets the light's plane at t; inside
    /// the disk the density in solid angle is t^2 / (|cos_light| area).
    float pdf(Vector3f w) const {
        const float cos_light = dot(w, frame.z);
        if (cos_light == 0) return 0;
        const float t = dot(centre, frame.z) / cos_light;
        if (!(t > 0)) return 0;
        const Vector3f d = t * w - centre;
        if (dot(d, d) > radius * radius) return 0;
        const float dist2 = distance_at_centre ? dot(centre, centre) : t * t;
        return dist2 / (std::abs(cos_light) * area());
    }
};

void add_disk_light(warpcheck::Registry& registry, const std::string& family, const std::string& description,
                    ObliqueDiskLight light) {
    registry.add_case(
        warpcheck::make_warp_case({.family = family, .description = description, .domain = Domain::sphere()}, light));
}

// --- An annulus 1e-4 wide ---------------------------------------------------------

struct Annulus {
    float r0 = 0.5f, r1 = 0.5001f;
    float sampled_r1 = r1;  // twin: sampled wider
    Point2f sample(Point2f u) const {
        const float r = std::sqrt(r0 * r0 + u.x * (sampled_r1 * sampled_r1 - r0 * r0));
        const float phi = 2 * kPi * u.y;
        return {r * std::cos(phi), r * std::sin(phi)};
    }
    float pdf(Point2f p) const {
        const float r = std::sqrt(p.x * p.x + p.y * p.y);
        return r >= r0 && r <= r1 ? 1 / (kPi * (r1 * r1 - r0 * r0)) : 0;
    }
};

// --- Densities infinite at an end ----------------------------------------------------

/// The largest float where a density exceeds float range (at or next to its
/// singular end): what a renderer that keeps its weights finite returns.
inline float finite(float pdf) { return std::fmin(pdf, std::numeric_limits<float>::max()); }

/// a x^(a - 1) on [0, 1], a < 1: x = u^(1/a), inverse x^a. At x = 0 (where
/// u^10 underflows, u < 3.2e-5) the density is infinite.
struct PowerEnd {
    float a;
    float sampled_a = a;
    float sample(float u) const { return std::pow(u, 1 / sampled_a); }
    float pdf(float x) const { return x >= 0 && x <= 1 ? finite(a * std::pow(x, a - 1)) : 0; }
};

/// The arcsine law 1 / (pi sqrt(x (1 - x))) on [0, 1]: x = sin^2(pi u / 2),
/// infinite at both ends.
struct Arcsine {
    float sample(float u) const {
        const float s = std::sin(kPi / 2 * u);
        return s * s;
    }
    float pdf(float x) const { return x >= 0 && x <= 1 ? finite(1 / (kPi * std::sqrt(x * (1 - x)))) : 0; }
};

/// Weibull with shape k < 1 on [0, inf): x = (-log(1 - u))^(1/k).
struct Weibull {
    float k;
    float sampled_k = k;
    float sample(float u) const { return std::pow(-std::log1p(-u), 1 / sampled_k); }
    float pdf(float x) const { return x >= 0 ? finite(k * std::pow(x, k - 1) * std::exp(-std::pow(x, k))) : 0; }
};

}  // namespace

void register_sharp_lobes(warpcheck::Registry& registry) {
    add_vmf(registry, "vmf", {1e6f});
    add_vmf(registry, "vmf_rings", {1e6f, true});
    mark_twin(registry, "vmf_rings[kappa=1000000]", "chi2,unbinned",
              "sin theta from the float cos theta: every sample on a few hundred rings, 3% at the pole");

    for (float alpha : {0.05f, 0.01f}) {
        add_beckmann(registry, "beckmann", {alpha});
        add_beckmann(registry, "beckmann_width_2pc_off", {alpha, 1.02f * alpha});
    }
    for (const char* alpha : {"0.05", "0.01"})
        mark_twin(registry, std::string("beckmann_width_2pc_off[alpha=") + alpha + "]", "chi2,unbinned",
                  "sampled with alpha 2% too large");

    add_ggx_visible(registry, "ggx_visible", 1e-3f, ggx_visible(1e-3f, 1e-3f, 60));
    add_ggx_visible(registry, "ggx_visible_width_2pc_off", 1e-3f, ggx_visible(1e-3f, 1.02e-3f, 60));
    mark_twin(registry, "ggx_visible_width_2pc_off[alpha=0.001,theta_o=60]", "chi2,unbinned",
              "sampled with alpha 2% too large");

    add_disk_light(registry, "disk_light_oblique", "a 4.8e-4 sr disk light 85 degrees off its normal, by area",
                   ObliqueDiskLight{});
    ObliqueDiskLight centred;
    centred.distance_at_centre = true;
    add_disk_light(registry, "disk_light_oblique_distance_at_centre",
                   "the oblique disk light with dist^2 taken at its centre", centred);
    mark_twin(registry, "disk_light_oblique_distance_at_centre", "chi2,unbinned",
              "the area-to-solid-angle conversion uses the centre's distance for every point");

    registry.add_case(warpcheck::make_warp_case({.family = "annulus",
                                                 .params = {{"width", 1e-4}},
                                                 .description = "uniform on a ring 1e-4 wide",
                                                 .domain = Domain::unit_disk()},
                                                Annulus{}));
    Annulus wide;
    wide.sampled_r1 = wide.r0 + 1.01f * (wide.r1 - wide.r0);
    registry.add_case(warpcheck::make_warp_case({.family = "annulus_sampled_1pc_wide",
                                                 .params = {{"width", 1e-4}},
                                                 .description = "the ring sampled 1% too wide",
                                                 .domain = Domain::unit_disk()},
                                                wide));
    mark_twin(registry, "annulus_sampled_1pc_wide[width=0.0001]", "consistency,chi2",
              "1% of the samples lie outside the ring the pdf describes");

    registry.add_case(warpcheck::make_warp_case({.family = "power_end",
                                                 .params = {{"a", 0.1}},
                                                 .description = "0.1 x^-0.9 on [0, 1], infinite at 0",
                                                 .domain = Domain::interval(0, 1)},
                                                PowerEnd{0.1f}));
    registry.add_case(warpcheck::make_warp_case({.family = "power_end_exponent_2pc_off",
                                                 .params = {{"a", 0.1}},
                                                 .description = "the power law sampled as u^10.2",
                                                 .domain = Domain::interval(0, 1)},
                                                PowerEnd{0.1f, 0.1f / 1.02f}));
    mark_twin(registry, "power_end_exponent_2pc_off[a=0.1]", "chi2,unbinned", "sampled as u^10.2, pdf for u^10");
    registry.add_case(warpcheck::make_warp_case({.family = "arcsine",
                                                 .description = "the arcsine law on [0, 1], infinite at both ends",
                                                 .domain = Domain::interval(0, 1)},
                                                Arcsine{}));
    registry.add_case(warpcheck::make_warp_case({.family = "weibull",
                                                 .params = {{"k", 0.5}},
                                                 .description = "Weibull with shape 1/2, infinite at 0",
                                                 .domain = Domain::half_line(0)},
                                                Weibull{0.5f}));
    registry.add_case(warpcheck::make_warp_case({.family = "weibull_shape_2pc_off",
                                                 .params = {{"k", 0.5}},
                                                 .description = "Weibull sampled with k 2% too small",
                                                 .domain = Domain::half_line(0)},
                                                Weibull{0.5f, 0.49f}));
    mark_twin(registry, "weibull_shape_2pc_off[k=0.5]", "chi2,unbinned", "sampled with k = 0.49, pdf for 0.5");
}

}  // namespace hard
