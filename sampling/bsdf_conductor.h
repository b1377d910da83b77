// A rough conductor: Trowbridge-Reitz (GGX) microfacets, isotropic or
// anisotropic, each a perfect mirror with the conductor's Fresnel reflectance,
// sampled by visible normals (sampling/trowbridge_reitz.h). Two-sided: a wo
// below the surface sees the same surface from below.
//
//   f(wo, wi) = D(wm) F(wo.wm) G2(wo, wi) / (4 |cos theta_o| |cos theta_i|),
//   wm = normalize(wo + wi),
//   pdf(wo, wi) = D_wo(wm) / (4 |wo.wm|) = G1(wo) D(wm) / (4 |cos theta_o|)
// (the visible-normal density times the Jacobian of reflection, dwm/dwi = 1 / (4 |wo.wm|)).
// The albedo is below 1 (below F): single scattering loses the energy that
// would bounce between microfacets, most at grazing angles and high roughness.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include "sampling/bsdf.h"
#include "sampling/bsdf_microfacet.h"

namespace warpcheck {

class RoughConductor {
public:
    /// eta + i k: the conductor's complex index of refraction (relative to the
    /// medium above), e.g. gold at 600 nm is about 0.25 + 3i.
    RoughConductor(const TrowbridgeReitz& distribution, float eta, float k) : tr_(distribution), eta_(eta), k_(k) {
        if (!(eta > 0.0f && std::isfinite(eta)) || !(k >= 0.0f && std::isfinite(k)))
            throw std::invalid_argument("rough_conductor: needs eta > 0 and k >= 0, got eta " + std::to_string(eta) +
                                        ", k " + std::to_string(k));
    }

    const TrowbridgeReitz& distribution() const { return tr_; }
    BsdfFlags flags() const { return BsdfFlags::Reflection | BsdfFlags::Continuous; }

    /// A visible normal wm seen from wo, and wi = wo mirrored about it; no
    /// sample where wi comes out on the other side (a shadowed reflection).
    /// uc is not used.
    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        (void)uc;
        if (wo.z == 0.0f) return {};
        const float side = wo.z > 0.0f ? 1.0f : -1.0f;
        const Vector3f up{wo.x, wo.y, side * wo.z};
        const Vector3f wm = tr_.visible_normals(up).sample(u);
        if (!has_side(wm)) return {};
        Vector3f wi = reflect(up, wm);
        if (!(wi.z > 0.0f)) return {};
        const float pdf = visible_normal_pdf(tr_, up, wm) / (4.0f * dot(up, wm));
        const float f = value(up, wi, wm);
        wi.z *= side;
        return {wi, f, pdf, flags()};
    }

    float f(Vector3f wo, Vector3f wi) const {
        if (!same_hemisphere(wo, wi)) return 0.0f;
        const Vector3f up_o = upper(wo), up_i = upper(wi), h = up_o + up_i;
        if (dot(h, h) == 0.0f) return 0.0f;
        return value(up_o, up_i, normalize(h));
    }

    float pdf(Vector3f wo, Vector3f wi) const {
        if (!same_hemisphere(wo, wi)) return 0.0f;
        const Vector3f up_o = upper(wo), h = up_o + upper(wi);
        if (dot(h, h) == 0.0f) return 0.0f;
        const Vector3f wm = normalize(h);
        const float cos_om = dot(up_o, wm);
        if (!(cos_om > 0.0f)) return 0.0f;
        return visible_normal_pdf(tr_, up_o, wm) / (4.0f * cos_om);
    }

private:
    /// The pair turned to the upper side (the surface seen from wo's side).
    static Vector3f upper(Vector3f w) { return {w.x, w.y, std::abs(w.z)}; }

    /// f for wo, wi above the surface and their half vector wm.
    float value(Vector3f wo, Vector3f wi, Vector3f wm) const {
        if (wo.z == 0.0f || wi.z == 0.0f) return 0.0f;
        const float fresnel = fresnel_conductor(std::abs(dot(wo, wm)), eta_, k_);
        return tr_.D(wm) * fresnel * smith_g2(tr_, wo, wi) / (4.0f * wo.z * wi.z);
    }

    TrowbridgeReitz tr_;
    float eta_, k_;
};

}  // namespace warpcheck
