// Dielectric interfaces (glass, water): an index of refraction eta below the
// surface (z < 0) over above. Light is reflected with the Fresnel reflectance
// F and refracted with 1 - F; the BSDF is sampled by choosing between the two
// with those probabilities, as pbrt-v4's DielectricBxDF does.
//  - SmoothDielectric: a flat interface, two delta lobes (mirror and Snell).
//  - RoughDielectric: Trowbridge-Reitz microfacets (Walter et al. 2007), each
//    a smooth interface, sampled by visible normals.
// Transmitted values carry 1 / etap^2 in Transport::Radiance (the default),
// none in Transport::Importance (sampling/bsdf.h).
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "sampling/bsdf.h"
#include "sampling/bsdf_microfacet.h"

namespace warpcheck {

namespace detail {

inline void check_eta(float eta, const char* who) {
    if (!(eta > 0.0f && std::isfinite(eta)) || eta == 1.0f)
        throw std::invalid_argument(std::string(who) + ": eta must be positive, finite and not 1, got " +
                                    std::to_string(eta));
}

/// 1 / etap^2 in radiance transport, else 1.
inline float transport_scale(Transport mode, float etap) { return mode == Transport::Radiance ? 1.0f / (etap * etap) : 1.0f; }

}  // namespace detail

/// A flat dielectric interface: reflection towards (-wo.x, -wo.y, wo.z) with
/// probability F(cos theta_o), refraction by Snell's law with 1 - F. f and
/// pdf are 0 everywhere (both lobes are delta); a sample's f is F / |cos theta_i|
/// (reflection) or (1 - F) / |cos theta_i| / etap^2 (transmission, radiance),
/// and its pdf the lobe's probability, so the weights are 1 and 1 / etap^2.
class SmoothDielectric {
public:
    explicit SmoothDielectric(float eta, Transport mode = Transport::Radiance) : eta_(eta), mode_(mode) {
        detail::check_eta(eta, "smooth_dielectric");
    }

    float eta() const { return eta_; }
    Transport transport() const { return mode_; }
    BsdfFlags flags() const { return BsdfFlags::Reflection | BsdfFlags::Transmission | BsdfFlags::Delta; }

    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        (void)u;
        if (wo.z == 0.0f) return {};
        const float r = fresnel_dielectric(wo.z, eta_), t = 1.0f - r;
        if (uc < r) {
            const Vector3f wi{-wo.x, -wo.y, wo.z};
            return {wi, r / std::abs(wi.z), r, BsdfFlags::Reflection | BsdfFlags::Delta};
        }
        float etap = 1.0f;
        Vector3f wi;
        if (!refract(wo, {0.0f, 0.0f, 1.0f}, eta_, etap, wi) || wi.z == 0.0f) return {};
        const float f = t / std::abs(wi.z) * detail::transport_scale(mode_, etap);
        return {wi, f, t, BsdfFlags::Transmission | BsdfFlags::Delta, etap};
    }

    float f(Vector3f, Vector3f) const { return 0.0f; }
    float pdf(Vector3f, Vector3f) const { return 0.0f; }

private:
    float eta_;
    Transport mode_;
};

/// A rough dielectric interface. With the generalised half vector
/// wm = face_up(etap wi + wo) (etap = 1 for reflection, eta(wi) / eta(wo) for
/// transmission) and F = F(wo.wm):
///   reflection:   f = D F G2 / (4 |cos_o cos_i|),
///                 pdf = D_wo(wm) / (4 |wo.wm|) F
///   transmission: f = D (1 - F) G2 |wi.wm wo.wm| / (|cos_o cos_i| (wi.wm + wo.wm / etap)^2) [/ etap^2],
///                 pdf = D_wo(wm) |wi.wm| / (wi.wm + wo.wm / etap)^2 (1 - F)
/// where D_wo is the visible-normal density; pairs whose wm faces away from
/// either direction have f = pdf = 0.
class RoughDielectric {
public:
    RoughDielectric(const TrowbridgeReitz& distribution, float eta, Transport mode = Transport::Radiance)
        : tr_(distribution), eta_(eta), mode_(mode) {
        detail::check_eta(eta, "rough_dielectric");
        // A transmission's generalised half vector wo + etap wi is at least
        // |etap - 1| long, and its float rounding is 2^-24 of 1: nearer 1 than
        // 2^-10 the microfacet normal it gives turns by more than 2^-14, and
        // f() and pdf() at the rounded wi are 0 for percents of the samples
        // (warpcheck --fuzz: 2% at eta = 1 + 10^-5 with alpha 0.1). From 2^-10
        // to 0.01 most samples still agree (the thin-lobe chi2 tests use
        // eta 1.001), but a weight at alpha 1 and edge inputs deep in the
        // microfacet tail (f ~ 1e-13) do not: an open finding, and the built-in
        // family's declared range starts at 1.01.
        if (std::abs(eta - 1.0f) < 0x1p-10f)
            throw std::invalid_argument("rough_dielectric: eta must differ from 1 by at least 2^-10 (the half vector "
                                        "wo + eta wi loses its direction to float rounding nearer 1), got " +
                                        std::to_string(eta));
    }

    float eta() const { return eta_; }
    Transport transport() const { return mode_; }
    BsdfFlags flags() const { return BsdfFlags::Reflection | BsdfFlags::Transmission | BsdfFlags::Continuous; }

    /// A visible normal wm seen from wo; reflection about it with probability
    /// F(wo.wm) (uc < F), refraction through it otherwise. No sample where the
    /// reflection comes out on the other side or the refraction on wo's side.
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        if (wo.z == 0.0f) return {};
        const Vector3f wm = tr_.visible_normals(wo).sample(u);
        if (!has_side(wm)) return {};
        const float cos_om = dot(wo, wm);
        const float r = fresnel_dielectric(cos_om, eta_), t = 1.0f - r;
        const float visible = visible_normal_pdf(tr_, wo, wm);
        if (uc < r) {
            const Vector3f wi = reflect(wo, wm);
            if (!same_hemisphere(wo, wi)) return {};
            const float f = tr_.D(wm) * r * smith_g2(tr_, wo, wi) / std::abs(4.0f * wi.z * wo.z);
            return {wi, f, visible / (4.0f * std::abs(cos_om)) * r, BsdfFlags::Reflection | BsdfFlags::Continuous};
        }
        float etap = 1.0f;
        Vector3f wi;
        if (!refract(wo, wm, eta_, etap, wi) || same_hemisphere(wo, wi) || wi.z == 0.0f) return {};
        const float cos_im = dot(wi, wm), sum = cos_im + cos_om / etap, denom = sum * sum;
        const float f = tr_.D(wm) * t * smith_g2(tr_, wo, wi) * std::abs(cos_im * cos_om / (wi.z * wo.z * denom)) *
                        detail::transport_scale(mode_, etap);
        const float pdf = visible * std::abs(cos_im) / denom * t;
        return {wi, f, pdf, BsdfFlags::Transmission | BsdfFlags::Continuous, etap};
    }

    float f(Vector3f wo, Vector3f wi) const {
        Geometry g;
        if (!geometry(wo, wi, g)) return 0.0f;
        const float fresnel = fresnel_dielectric(g.cos_om, eta_);
        const float d_g2 = tr_.D(g.wm) * smith_g2(tr_, wo, wi);
        if (g.reflection) return d_g2 * fresnel / std::abs(4.0f * wi.z * wo.z);
        const float sum = g.cos_im + g.cos_om / g.etap;
        return d_g2 * (1.0f - fresnel) * std::abs(g.cos_im * g.cos_om / (wi.z * wo.z * sum * sum)) *
               detail::transport_scale(mode_, g.etap);
    }

    float pdf(Vector3f wo, Vector3f wi) const {
        Geometry g;
        if (!geometry(wo, wi, g)) return 0.0f;
        const float r = fresnel_dielectric(g.cos_om, eta_);
        const float visible = visible_normal_pdf(tr_, wo, g.wm);
        if (g.reflection) return visible / (4.0f * std::abs(g.cos_om)) * r;
        const float sum = g.cos_im + g.cos_om / g.etap;
        return visible * std::abs(g.cos_im) / (sum * sum) * (1.0f - r);
    }

private:
    struct Geometry {
        bool reflection = true;
        float etap = 1.0f;
        Vector3f wm;
        float cos_om = 0.0f, cos_im = 0.0f;
    };

    /// The generalised half vector of (wo, wi) and the cosines with it; false
    /// where f and pdf are 0 (a direction on the horizon, a degenerate half
    /// vector, a microfacet facing away from either direction).
    bool geometry(Vector3f wo, Vector3f wi, Geometry& g) const {
        if (wo.z == 0.0f || wi.z == 0.0f) return false;
        g.reflection = same_hemisphere(wo, wi);
        g.etap = g.reflection ? 1.0f : (wo.z > 0.0f ? eta_ : 1.0f / eta_);
        const Vector3f h = g.etap * wi + wo;
        if (dot(h, h) == 0.0f) return false;
        g.wm = face_up(normalize(h));
        g.cos_om = dot(wo, g.wm);
        g.cos_im = dot(wi, g.wm);
        return g.cos_im * wi.z > 0.0f && g.cos_om * wo.z > 0.0f;
    }

    TrowbridgeReitz tr_;
    float eta_;
    Transport mode_;
};

}  // namespace warpcheck
