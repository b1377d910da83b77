// A coated BSDF as renderers ship layered materials (pbrt-v4's CoatedDiffuse
// and CoatedConductor, without a medium between the layers): a smooth
// dielectric coat of index eta over a base BSDF that reflects only (a
// Lambertian, a rough conductor), evaluated and sampled by random walks
// between the two layers. Two-sided: a wo below the surface sees it from below.
//
// What it promises is stochastic (BsdfClaims::stochastic):
//  - f(wo, wi) is a one-sample estimate whose expectation is the layered f,
//        T(wo) T(wi) / eta^2 * sum over k >= 0 of the k-fold internal bounces
//        S_k(wo', wi'), S_0 = base.f(wo', wi'),
//    T = 1 - F the coat's transmittance, wo' and wi' the directions refracted
//    into the layer; the walk from wo' samples the base, continues with the
//    probability F of an internal reflection, and adds base.f toward wi' at
//    every base vertex (next-event estimation). The random numbers come from a
//    hash of wo's and wi's bits and the BSDF's seed, as in pbrt, so a pair
//    always gets the same estimate and different pairs independent ones.
//  - sample(wo, uc, u) returns the coat's mirror reflection with probability
//    F(wo) (a delta lobe, weight 1), else a walk's exit direction with its
//    throughput f |cos theta_i| / pdf (the product of the base's weights); its
//    f and pdf are only that ratio's parts: the pdf is pdf(wo, wi), not the
//    density the walk draws from (pbrt's pdfIsProportional).
//  - pdf(wo, wi) is an approximation kept for multiple importance sampling:
//    the single-bounce density mixed with a uniform hemisphere, positive
//    wherever the walk can exit.
// For a Lambertian base the expectation has a closed form,
//     f = T(wo) T(wi) R / (pi eta^2 (1 - R r_i)),
// r_i the coat's cosine-weighted internal reflectance (tests/sampling holds
// the walks' mean to it).
#pragma once

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "sampling/bsdf.h"
#include "sampling/float_bits.h"
#include "sampling/hash.h"
#include "sampling/pcg32.h"

namespace warpcheck {

/// Planted errors of the coated BSDF, for the known-bad catalogue.
enum class CoatFlaw : uint8_t {
    None,
    /// f's coat transmittance by Schlick's approximation, the sampler's by
    /// the exact Fresnel term: a few percent at grazing angles.
    SchlickInF,
    /// The sampler scales the base's albedo by 1.02 at every bounce.
    AlbedoInSample,
    /// f omits the radiance compression 1 / eta^2 on the paths that bounce
    /// inside the coat (k >= 1), a missing refraction Jacobian in one path.
    JacobianInF,
    /// The coat's transmittance where the light enters (f's first direction,
    /// the sampler's wo) by Schlick's approximation, where it leaves by the
    /// exact Fresnel term, in f and in the sampler alike (the sampler's
    /// weights follow f's terms), while f(wo, wi) and f(wi, wo) differ by the
    /// two approximations' ratio at wo over that at wi (a few percent at
    /// grazing angles): not reciprocal.
    SchlickAtEntry,
};

template <typename Base>
class CoatedBsdf {
public:
    /// Walks stop after this many base vertices: the estimate then drops the
    /// rest, at most (the base's albedo times r_i)^64 of the value, below 1e-7
    /// for any albedo up to 0.99 under a coat of eta <= 4 (r_i <= 0.9).
    static constexpr int kMaxVertices = 64;

    /// eta: the coat's index over the medium above (finite, positive, not 1).
    CoatedBsdf(Base base, float eta, uint64_t seed = 0, CoatFlaw flaw = CoatFlaw::None)
        : base_(std::move(base)), eta_(eta), seed_(seed), flaw_(flaw) {
        if (!(eta > 0.0f && std::isfinite(eta)) || eta == 1.0f)
            throw std::invalid_argument("coated: eta must be positive, finite and not 1, got " + std::to_string(eta));
    }

    const Base& base() const { return base_; }
    BsdfFlags flags() const { return BsdfFlags::Reflection | BsdfFlags::Continuous | BsdfFlags::Delta; }

    BsdfSample sample(Vector3f wo, float uc, Point2f u) const {
        if (wo.z == 0.0f) return {};
        const float side = wo.z > 0.0f ? 1.0f : -1.0f;
        const float fo = flaw_ == CoatFlaw::SchlickAtEntry ? schlick(std::abs(wo.z)) : fresnel_dielectric(std::abs(wo.z), eta_);
        if (uc < fo) return {{-wo.x, -wo.y, wo.z}, fo / std::abs(wo.z), fo, BsdfFlags::Reflection | BsdfFlags::Delta};
        Vector3f w;
        if (!inside(upper(wo), w)) return {};
        Pcg32 rng(hash_values(float_to_bits(uc), float_to_bits(u.x), float_to_bits(u.y)), seed_);
        float beta = 1.0f;
        for (int vertex = 0; vertex < kMaxVertices; ++vertex) {
            const BsdfSample b = base_.sample(w, rng.next_float(), {rng.next_float(), rng.next_float()});
            if (!(b.pdf > 0.0f) || !(b.wi.z > 0.0f) || has(b.flags, BsdfFlags::Delta)) return {};
            beta *= b.f * b.wi.z / b.pdf;
            if (flaw_ == CoatFlaw::AlbedoInSample) beta *= 1.02f;
            const Vector3f v = b.wi;  // up, toward the coat
            if (rng.next_float() < fresnel_dielectric(-v.z, eta_)) {
                w = {-v.x, -v.y, v.z};  // reflected back down: the base sees the path come from there
                continue;
            }
            float etap = 1.0f;
            Vector3f wi;
            if (!refract(-1.0f * v, {0.0f, 0.0f, 1.0f}, eta_, etap, wi) || !(wi.z > 0.0f)) return {};
            wi.z *= side;
            const float pdf = this->pdf(wo, wi);
            if (!(pdf > 0.0f)) return {};
            return {wi, beta * pdf / std::abs(wi.z), pdf, BsdfFlags::Reflection | BsdfFlags::Continuous};
        }
        return {};
    }

    float f(Vector3f wo, Vector3f wi) const {
        if (!same_hemisphere(wo, wi)) return 0.0f;
        const Vector3f up_o = upper(wo), up_i = upper(wi);
        Vector3f w, wi_in;
        if (!inside(up_o, w) || !inside(up_i, wi_in)) return 0.0f;
        Pcg32 rng(hash_values(float_to_bits(wo.x), float_to_bits(wo.y), float_to_bits(wo.z), float_to_bits(wi.x),
                              float_to_bits(wi.y), float_to_bits(wi.z)),
                  seed_);
        float first = base_.f(w, wi_in), rest = 0.0f, beta = 1.0f;
        for (int vertex = 1; vertex < kMaxVertices; ++vertex) {
            const BsdfSample b = base_.sample(w, rng.next_float(), {rng.next_float(), rng.next_float()});
            if (!(b.pdf > 0.0f) || !(b.wi.z > 0.0f) || has(b.flags, BsdfFlags::Delta)) break;
            beta *= b.f * b.wi.z / b.pdf;
            const Vector3f v = b.wi;
            if (!(rng.next_float() < fresnel_dielectric(-v.z, eta_))) break;  // it leaves: no path to wi
            w = {-v.x, -v.y, v.z};
            rest += beta * base_.f(w, wi_in);
        }
        const float compression = 1.0f / (eta_ * eta_);
        const float paths = first + (flaw_ == CoatFlaw::JacobianInF ? rest * eta_ * eta_ : rest);
        const float entry = flaw_ == CoatFlaw::SchlickAtEntry ? 1.0f - schlick(up_o.z) : transmittance_in_f(up_o.z);
        return entry * transmittance_in_f(up_i.z) * compression * paths;
    }

    /// (1 - F(wo)) times the mixture of a quarter uniform over the hemisphere
    /// and three quarters the single-bounce density (the base's pdf inside
    /// the coat, carried out through the refraction's Jacobian
    /// cos theta_i / (eta^2 cos theta_i')): not the walk's density.
    float pdf(Vector3f wo, Vector3f wi) const {
        if (!same_hemisphere(wo, wi)) return 0.0f;
        const Vector3f up_o = upper(wo), up_i = upper(wi);
        Vector3f w, wi_in;
        if (!inside(up_o, w) || !inside(up_i, wi_in) || !(wi_in.z > 0.0f)) return 0.0f;
        const float single = base_.pdf(w, wi_in) * up_i.z / (eta_ * eta_ * wi_in.z);
        return (1.0f - fresnel_dielectric(up_o.z, eta_)) * (0.25f * kInvTwoPi + 0.75f * single);
    }

private:
    static constexpr float kInvTwoPi = 0.15915494309189535f;
    static Vector3f upper(Vector3f w) { return {w.x, w.y, std::abs(w.z)}; }

    /// The direction inside the coat, pointing up, of the light that crosses
    /// it along the upper direction w (Snell; always possible from above).
    bool inside(Vector3f w, Vector3f& in) const {
        float etap = 1.0f;
        Vector3f t;
        if (!refract(w, {0.0f, 0.0f, 1.0f}, eta_, etap, t)) return false;
        in = -1.0f * t;
        return in.z > 0.0f;
    }

    /// Schlick's approximation of the coat's Fresnel reflectance.
    float schlick(float cos_theta) const {
        const float r0 = (eta_ - 1.0f) * (eta_ - 1.0f) / ((eta_ + 1.0f) * (eta_ + 1.0f));
        const float m = 1.0f - cos_theta;
        return r0 + (1.0f - r0) * m * m * m * m * m;
    }

    float transmittance_in_f(float cos_theta) const {
        if (flaw_ == CoatFlaw::SchlickInF) return 1.0f - schlick(cos_theta);
        return 1.0f - fresnel_dielectric(cos_theta, eta_);
    }

    Base base_;
    float eta_;
    uint64_t seed_;
    CoatFlaw flaw_;
};

}  // namespace warpcheck
