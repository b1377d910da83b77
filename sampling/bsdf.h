// What every BSDF and phase function of sampling/bsdf_*.h shares: the sample
// they return, the flags of their lobes, and the optics of a smooth interface
// (mirror reflection, refraction by Snell's law, the dielectric Fresnel
// reflectance) in the shading frame (z is the normal; wo and wi point away
// from the surface).
//
// The shape of a BSDF here is pbrt-v4's BxDF, so that a renderer's own can be
// checked as it is: sample(wo, uc, u) -> BsdfSample, f(wo, wi), pdf(wo, wi),
// flags(). wo is the direction towards the viewer; wi is sampled; the
// estimator's weight is f |cos theta_i| / pdf (a phase function's p / pdf).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "sampling/math.h"
#include "sampling/vector.h"

namespace warpcheck {

/// What a lobe does (pbrt's BxDFFlags, reduced to what the checks test). A
/// BSDF's flags() is the union over its lobes; a sample's flags are its lobe's.
enum class BsdfFlags : uint8_t {
    None = 0,
    Reflection = 1,    ///< wi on wo's side of the surface
    Transmission = 2,  ///< wi on the other side
    Continuous = 4,    ///< a density over directions (pbrt's diffuse or glossy)
    Delta = 8,         ///< one direction, chosen with a probability (pbrt's specular)
};

constexpr BsdfFlags operator|(BsdfFlags a, BsdfFlags b) {
    return static_cast<BsdfFlags>(static_cast<uint8_t>(a) | static_cast<uint8_t>(b));
}
/// Whether `flags` has every bit of `of`.
constexpr bool has(BsdfFlags flags, BsdfFlags of) {
    return (static_cast<uint8_t>(flags) & static_cast<uint8_t>(of)) == static_cast<uint8_t>(of);
}

/// How transmission values scale with the indices of refraction (pbrt's
/// TransportMode). Radiance: f carries 1 / etap^2 across an interface (radiance
/// is compressed into the denser medium), so f(wo, wi) / eta(wo)^2 is symmetric,
/// eta(w) being the index on w's side; Importance: no factor, so f(wo, wi) /
/// eta(wi)^2 is symmetric. Reflection is symmetric in both.
enum class Transport : uint8_t { Radiance, Importance };

/// One sample of a BSDF. pdf == 0 means that there is no sample (the sampler
/// gave up: a reflection below the horizon, a refraction beyond the critical
/// angle); it counts as a sample of weight 0.
struct BsdfSample {
    Vector3f wi;
    /// f(wo, wi); for a delta lobe, the value whose f |cos theta_i| / pdf is the weight.
    float f = 0.0f;
    /// Density per solid angle of wi; for a delta lobe, the probability of choosing it.
    float pdf = 0.0f;
    BsdfFlags flags = BsdfFlags::None;
    /// For transmission: the relative index of refraction eta(wi's side) / eta(wo's side).
    float eta = 1.0f;
};

/// One sample of a spectral BSDF with N channels (RGB: 3; hero-wavelength
/// sampling: N wavelengths, the hero first or anywhere): wi drawn with the
/// hero channel's density; per channel c, f[c] = f_c(wo, wi), and pdf[c] the
/// density channel c's own sampler has at wi (what hero-wavelength MIS
/// combines), or 0 where channel c is terminated (pbrt-v4's
/// TerminateSecondary: a dispersive refraction's secondary wavelengths).
/// For a delta lobe, f[c] and pdf[c] as BsdfSample's.
template <std::size_t N>
struct SpectralSample {
    Vector3f wi{};
    std::array<float, N> f{};
    std::array<float, N> pdf{};
    BsdfFlags flags = BsdfFlags::None;
    float eta = 1.0f;  ///< the hero channel's, for transmission
};

/// Whether a and b lie on the same side of the surface (z = 0 counts as neither).
inline bool same_hemisphere(Vector3f a, Vector3f b) { return a.z * b.z > 0.0f; }

/// The mirror image of w about the normal n: 2 (w.n) n - w.
inline Vector3f reflect(Vector3f w, Vector3f n) { return (2.0f * dot(w, n)) * n - w; }

/// The direction refracted from w through a surface with normal n, where eta is
/// the index of n's far side over its near side (the interface's index below
/// over above for n = +z); w and n on the same side or not (then the roles
/// swap, and 1/eta applies). Returns false at total internal reflection;
/// `etap` gets the relative index that applied. Snell: sin theta_t = sin theta_i / etap.
inline bool refract(Vector3f w, Vector3f n, float eta, float& etap, Vector3f& wt) {
    float cos_i = dot(n, w);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
        n = -1.0f * n;
    }
    const float sin2_i = std::max(0.0f, (1.0f - cos_i) * (1.0f + cos_i));
    const float sin2_t = sin2_i / (eta * eta);
    if (sin2_t >= 1.0f) return false;
    const float cos_t = safe_sqrt(1.0f - sin2_t);
    wt = (-1.0f / eta) * w + (cos_i / eta - cos_t) * n;
    etap = eta;
    return true;
}

/// The Fresnel reflectance of unpolarised light at a smooth dielectric
/// interface (the mean of the s and p reflectances) for cos theta_i = cos_i
/// measured on the side where it is positive; eta is the index below over
/// above, and a negative cos_i means the light arrives from below (1/eta
/// applies). 1 at total internal reflection.
inline float fresnel_dielectric(float cos_i, float eta) {
    cos_i = std::clamp(cos_i, -1.0f, 1.0f);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
    }
    const float sin2_t = (1.0f - cos_i) * (1.0f + cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;
    const float cos_t = safe_sqrt(1.0f - sin2_t);
    const float r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_parl * r_parl + r_perp * r_perp);
}

/// The Fresnel reflectance of a conductor with complex index eta + i k (the
/// exact formula for unpolarised light, in float), for cos_i in [0, 1].
inline float fresnel_conductor(float cos_i, float eta, float k) {
    // With a^2 + b^2 = sqrt((eta^2 - k^2 - sin^2)^2 + 4 eta^2 k^2) and
    // 2 a^2 = that + eta^2 - k^2 - sin^2 (Born and Wolf's intermediate terms).
    cos_i = std::clamp(cos_i, 0.0f, 1.0f);
    const float cos2 = cos_i * cos_i, sin2 = 1.0f - cos2;
    const float t0 = eta * eta - k * k - sin2;
    const float a2_plus_b2 = std::sqrt(t0 * t0 + 4.0f * eta * eta * k * k);
    const float a = safe_sqrt(0.5f * (a2_plus_b2 + t0));
    const float t1 = a2_plus_b2 + cos2, t2 = 2.0f * cos_i * a;
    const float rs = (t1 - t2) / (t1 + t2);
    const float t3 = cos2 * a2_plus_b2 + sin2 * sin2, t4 = t2 * sin2;
    const float rp = rs * (t3 - t4) / (t3 + t4);
    return 0.5f * (rp + rs);
}

/// An orthonormal basis (t, b, n) around the unit vector n without a branch
/// on which axis is smallest (Duff et al. 2017, "Building an orthonormal basis,
/// revisited"): continuous except across n.z = 0's sign change.
struct Frame {
    Vector3f t, b, n;
    static Frame around(Vector3f n) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sign + n.z);
        const float c = n.x * n.y * a;
        return {{1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x}, {c, sign + n.y * n.y * a, -n.y}, n};
    }
    /// The direction with local coordinates (x, y, z) in this frame.
    Vector3f to_world(float x, float y, float z) const { return x * t + y * b + z * n; }
};

}  // namespace warpcheck
