// Plastic: a diffuse base under a dielectric coat, as a mixture of two lobes
// chosen by a Fresnel weight, the way many renderers write it:
//  - specular: the coat's reflection, a mirror (alpha = 0: a delta lobe) or a
//    Trowbridge-Reitz microfacet lobe (alpha > 0), with Fresnel F;
//  - diffuse: kd / pi (1 - F(cos theta_o)) (1 - F(cos theta_i)), the light
//    that enters the coat, is scattered by the base and leaves it.
// Sampling picks the specular lobe with probability Ps = F(|cos theta_o|) (the
// Fresnel weight at the macro normal), the diffuse one otherwise; the pdf of a
// direction is the mixture of both lobes' pdfs. f is symmetric in wo and wi.
#pragma once

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "sampling/bsdf.h"
#include "sampling/bsdf_microfacet.h"
#include "sampling/hemisphere.h"

namespace warpcheck {

class Plastic {
public:
    /// kd in [0, 1]; eta the coat's index (not 1); alpha = 0 for a smooth coat,
    /// else the Trowbridge-Reitz roughness (TrowbridgeReitz's range).
    Plastic(float kd, float eta, float alpha) : kd_(kd), eta_(eta) {
        if (!(kd >= 0.0f && kd <= 1.0f)) throw std::invalid_argument("plastic: kd must lie in [0, 1], got " + std::to_string(kd));
        if (!(eta > 0.0f && std::isfinite(eta)) || eta == 1.0f)
            throw std::invalid_argument("plastic: eta must be positive, finite and not 1, got " + std::to_string(eta));
        if (alpha != 0.0f) tr_.emplace(alpha);
    }

    BsdfFlags flags() const {
        return BsdfFlags::Reflection | BsdfFlags::Continuous | (tr_ ? BsdfFlags::None : BsdfFlags::Delta);
    }

    /// The probability of choosing the specular lobe: F(|cos theta_o|).
    float specular_probability(Vector3f wo) const { return fresnel_dielectric(std::abs(wo.z), eta_); }

    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        if (wo.z == 0.0f) return {};
        const float side = wo.z > 0.0f ? 1.0f : -1.0f;
        const Vector3f up{wo.x, wo.y, side * wo.z};
        const float ps = specular_probability(wo);
        Vector3f wi;
        if (uc < ps) {
            if (!tr_) return {{-wo.x, -wo.y, wo.z}, ps / std::abs(wo.z), ps, BsdfFlags::Reflection | BsdfFlags::Delta};
            const Vector3f wm = tr_->visible_normals(up).sample(u);
            if (!has_side(wm)) return {};
            wi = reflect(up, wm);
        } else {
            wi = CosineHemisphere{}.sample(u);
        }
        if (!(wi.z > 0.0f)) return {};
        wi.z *= side;
        const float pdf = this->pdf(wo, wi);
        if (!(pdf > 0.0f)) return {};
        return {wi, f(wo, wi), pdf, BsdfFlags::Reflection | BsdfFlags::Continuous};
    }

    float f(Vector3f wo, Vector3f wi) const {
        if (!same_hemisphere(wo, wi)) return 0.0f;
        const float co = std::abs(wo.z), ci = std::abs(wi.z);
        float value = kd_ * kInvPi * (1.0f - fresnel_dielectric(co, eta_)) * (1.0f - fresnel_dielectric(ci, eta_));
        if (tr_) {
            const Vector3f up_o{wo.x, wo.y, co}, up_i{wi.x, wi.y, ci}, h = up_o + up_i;
            if (dot(h, h) > 0.0f) {
                const Vector3f wm = normalize(h);
                value += tr_->D(wm) * fresnel_dielectric(dot(up_o, wm), eta_) * smith_g2(*tr_, up_o, up_i) /
                         (4.0f * co * ci);
            }
        }
        return value;
    }

    /// The mixture (1 - Ps) |cos theta_i| / pi + Ps pdf_specular on wo's side
    /// (the smooth coat's delta lobe has no density).
    float pdf(Vector3f wo, Vector3f wi) const {
        if (!same_hemisphere(wo, wi)) return 0.0f;
        const float ps = specular_probability(wo);
        float value = (1.0f - ps) * std::abs(wi.z) * kInvPi;
        if (tr_) {
            const Vector3f up_o{wo.x, wo.y, std::abs(wo.z)}, h = up_o + Vector3f{wi.x, wi.y, std::abs(wi.z)};
            if (dot(h, h) > 0.0f) {
                const Vector3f wm = normalize(h);
                const float cos_om = dot(up_o, wm);
                if (cos_om > 0.0f) value += ps * visible_normal_pdf(*tr_, up_o, wm) / (4.0f * cos_om);
            }
        }
        return value;
    }

private:
    float kd_, eta_;
    std::optional<TrowbridgeReitz> tr_;
};

}  // namespace warpcheck
