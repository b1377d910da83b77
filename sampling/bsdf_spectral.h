// Spectral BSDFs (sampling/bsdf.h's SpectralSample): values per channel, a
// direction drawn with one channel, the hero, as renderers that sample RGB or
// a few wavelengths at once do.
//  - RgbConductor: a rough conductor whose Fresnel term differs per channel
//    (complex index per R, G, B) over one microfacet distribution: the pdf is
//    the same in every channel, only f differs.
//  - DispersiveDielectric: a rough dielectric whose index differs per
//    wavelength (dispersion): every channel's pdf differs (the Fresnel choice
//    of reflection and the refraction's half vector depend on eta), so a
//    transmission terminates the secondary channels (pdf 0, as pbrt-v4's
//    TerminateSecondary), and a reflection reports each channel's own pdf.
// Each has planted flaws for the known-bad catalogue.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "sampling/bsdf.h"
#include "sampling/bsdf_conductor.h"
#include "sampling/bsdf_dielectric.h"

namespace warpcheck {

enum class SpectralFlaw : uint8_t {
    None,
    /// The sample's f in channel 1 (green) is 0.5% high: its weight is.
    GreenWeightHigh,
    /// A transmission reports the hero's pdf for the secondary channels
    /// instead of terminating them: their MIS weights use the wrong density.
    SecondaryNotTerminated,
    /// The secondary channels' f is the hero's dielectric's (its eta), as if
    /// the secondary wavelengths refracted like the hero.
    SecondaryWithHeroEta,
};

/// Gold in R, G, B: eta + i k at about 650, 550 and 450 nm (published tables).
inline constexpr std::array<float, 3> kGoldRgbEta{0.143f, 0.374f, 1.442f}, kGoldRgbK{3.983f, 2.385f, 1.603f};

class RgbConductor {
public:
    RgbConductor(const TrowbridgeReitz& distribution, std::array<float, 3> eta, std::array<float, 3> k,
                 SpectralFlaw flaw = SpectralFlaw::None)
        : channels_{RoughConductor(distribution, eta[0], k[0]), RoughConductor(distribution, eta[1], k[1]),
                    RoughConductor(distribution, eta[2], k[2])},
          flaw_(flaw) {}

    BsdfFlags flags() const { return channels_[0].flags(); }

    /// sample()'s hero channel alone (its wi, f, pdf, flags): the fast path
    /// of the checks that see one channel.
    BsdfSample sample_hero(Vector3f wo, float uc, Point2f u, int hero) const {
        BsdfSample s = channels_[static_cast<std::size_t>(hero)].sample(wo, uc, u);
        if (flaw_ == SpectralFlaw::GreenWeightHigh && hero == 1 && s.pdf > 0.0f) s.f *= 1.005f;
        return s;
    }

    SpectralSample<3> sample(Vector3f wo, float uc, Point2f u, int hero) const {
        const BsdfSample s = channels_[static_cast<std::size_t>(hero)].sample(wo, uc, u);
        SpectralSample<3> out{s.wi, {}, {}, s.flags, s.eta};
        if (!(s.pdf > 0.0f)) return out;
        // Every channel on the sampled microfacet, as one spectral evaluation
        // is: the hero's value times each channel's Fresnel ratio at wi.
        const std::array<float, 3> at = f(wo, s.wi);
        const auto h = static_cast<std::size_t>(hero);
        for (std::size_t c = 0; c < 3; ++c) {
            out.f[c] = c == h ? s.f : at[h] > 0.0f ? s.f * (at[c] / at[h]) : at[c];
            out.pdf[c] = s.pdf;  // one distribution: the same density in every channel
        }
        if (flaw_ == SpectralFlaw::GreenWeightHigh) out.f[1] *= 1.005f;
        return out;
    }
    std::array<float, 3> f(Vector3f wo, Vector3f wi) const {
        return {channels_[0].f(wo, wi), channels_[1].f(wo, wi), channels_[2].f(wo, wi)};
    }
    std::array<float, 3> pdf(Vector3f wo, Vector3f wi) const {
        const float p = channels_[0].pdf(wo, wi);
        return {p, p, p};
    }
    float f(Vector3f wo, Vector3f wi, int channel) const { return channels_[static_cast<std::size_t>(channel)].f(wo, wi); }
    float pdf(Vector3f wo, Vector3f wi, int) const { return channels_[0].pdf(wo, wi); }

private:
    std::array<RoughConductor, 3> channels_;
    SpectralFlaw flaw_;
};

/// N wavelengths of a rough dielectric, each with its own index.
template <std::size_t N>
class DispersiveDielectric {
public:
    DispersiveDielectric(const TrowbridgeReitz& distribution, std::array<float, N> eta,
                         SpectralFlaw flaw = SpectralFlaw::None)
        : channels_(make(distribution, eta)), flaw_(flaw) {}

    BsdfFlags flags() const { return channels_[0].flags(); }
    float eta(int channel) const { return channels_[static_cast<std::size_t>(channel)].eta(); }

    /// sample()'s hero channel alone: the fast path of the one-channel checks.
    BsdfSample sample_hero(Vector3f wo, float uc, Point2f u, int hero) const {
        return channels_[static_cast<std::size_t>(hero)].sample(wo, uc, u);
    }

    SpectralSample<N> sample(Vector3f wo, float uc, Point2f u, int hero) const {
        const auto h = static_cast<std::size_t>(hero);
        const BsdfSample s = channels_[h].sample(wo, uc, u);
        SpectralSample<N> out{s.wi, {}, {}, s.flags, s.eta};
        if (!(s.pdf > 0.0f)) return out;
        const bool transmitted = has(s.flags, BsdfFlags::Transmission);
        // Each secondary as the hero's sampled value times their ratio at wi
        // (one spectral evaluation on the sampled microfacet).
        const float fh = channels_[h].f(wo, s.wi), ph = channels_[h].pdf(wo, s.wi);
        out.f[h] = s.f;
        out.pdf[h] = s.pdf;
        for (std::size_t c = 0; c < N; ++c) {
            if (c == h) continue;
            const RoughDielectric& d = flaw_ == SpectralFlaw::SecondaryWithHeroEta ? channels_[h] : channels_[c];
            const float fc = d.f(wo, s.wi);
            out.f[c] = fh > 0.0f ? s.f * (fc / fh) : fc;
            if (transmitted) {
                out.pdf[c] = flaw_ == SpectralFlaw::SecondaryNotTerminated ? s.pdf : 0.0f;
            } else {
                const float pc = channels_[c].pdf(wo, s.wi);
                out.pdf[c] = ph > 0.0f ? s.pdf * (pc / ph) : pc;
            }
        }
        return out;
    }
    std::array<float, N> f(Vector3f wo, Vector3f wi) const {
        std::array<float, N> out{};
        for (std::size_t c = 0; c < N; ++c) out[c] = channels_[c].f(wo, wi);
        return out;
    }
    std::array<float, N> pdf(Vector3f wo, Vector3f wi) const {
        std::array<float, N> out{};
        for (std::size_t c = 0; c < N; ++c) out[c] = channels_[c].pdf(wo, wi);
        return out;
    }
    float f(Vector3f wo, Vector3f wi, int channel) const { return channels_[static_cast<std::size_t>(channel)].f(wo, wi); }
    float pdf(Vector3f wo, Vector3f wi, int channel) const {
        return channels_[static_cast<std::size_t>(channel)].pdf(wo, wi);
    }

private:
    static std::array<RoughDielectric, N> make(const TrowbridgeReitz& distribution, std::array<float, N> eta) {
        return make(distribution, eta, std::make_index_sequence<N>{});
    }
    template <std::size_t... I>
    static std::array<RoughDielectric, N> make(const TrowbridgeReitz& distribution, std::array<float, N> eta,
                                               std::index_sequence<I...>) {
        return {RoughDielectric(distribution, eta[I])...};
    }

    std::array<RoughDielectric, N> channels_;
    SpectralFlaw flaw_;
};

}  // namespace warpcheck
