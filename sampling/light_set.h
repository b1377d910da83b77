// Several lights sampled as one, a light chosen by a pmf: what a renderer's
// light sampler does before it samples the light it chose (pbrt-v4's
// UniformLightSampler and PowerLightSampler, reduced to a fixed pmf).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "sampling/light_sample.h"
#include "sampling/math.h"
#include "sampling/vector.h"

namespace warpcheck {

/// Tag for the LightSet whose lights overlap as seen from ref (an environment
/// map behind the others).
struct OverlappingLights {};
inline constexpr OverlappingLights kOverlappingLights{};

/// Lights chosen by a pmf: u.x picks light i with probability pmf[i] and is
/// remapped to [0, 1) within its share, so that the chosen light samples from
/// (u.x', u.y). The density of a direction is the sum over the lights of
/// pmf[i] pdf_i(ref, wi), and L is the sum of the lights' L (emitters that do
/// not occlude each other: what a light sampler estimates before its shadow
/// rays). A light of pmf 0 is never chosen, and its density does not count.
///
/// By default a sample returns its light's pmf times its pdf, and its light's
/// L: the set's density and L where the lights do not overlap as seen from
/// ref, which that constructor assumes. Built with kOverlappingLights, a
/// sample returns the set's pdf(ref, wi) and L(ref, wi) at its direction
/// instead: where another light also shines there (an environment map does
/// everywhere), the chosen light's pmf times its pdf is not the density the
/// set draws from, and MIS must weigh the set's (it costs every light's pdf
/// and L per sample).
template <typename... Lights>
class LightSet {
public:
    static constexpr std::size_t kCount = sizeof...(Lights);

    explicit LightSet(std::array<float, kCount> pmf, Lights... lights) : pmf_(pmf), lights_(std::move(lights)...) {
        check_pmf();
    }
    LightSet(OverlappingLights, std::array<float, kCount> pmf, Lights... lights)
        : LightSet(pmf, std::move(lights)...) {
        overlapping_ = true;
    }

    LightSample sample(Vector3f ref, Point2f u) const {
        // The light whose share of [0, 1) holds u.x: the last one with a
        // share takes what rounding leaves past the shares' float sum.
        std::size_t chosen = 0;
        float start = 0.0f;
        for (std::size_t i = 0; i < kCount; ++i) {
            if (pmf_[i] == 0.0f) continue;
            chosen = i;
            if (u.x < start + pmf_[i]) break;
            start += pmf_[i];
        }
        const float remapped = std::clamp((u.x - start) / pmf_[chosen], 0.0f, kOneMinusEpsilon);
        LightSample s = sample_light(chosen, ref, {remapped, u.y});
        if (!overlapping_) {
            s.pdf *= pmf_[chosen];
            return s;
        }
        if (s.pdf == 0.0f) return s;  // no sample
        // The set's density and radiance where the direction is, as pdf() and
        // L() find them (a direction rounded off its light finds the others').
        s.pdf = pdf(ref, s.wi);
        s.L = L(ref, s.wi);
        if (!(s.pdf > 0.0f)) return {};
        return s;
    }

    /// Whether the set was built with kOverlappingLights.
    bool overlapping() const { return overlapping_; }

    float pdf(Vector3f ref, Vector3f wi) const {
        return std::apply(
            [&](const auto&... light) {
                std::size_t i = 0;
                float sum = 0.0f;
                ((sum += pmf_[i] > 0.0f ? pmf_[i] * static_cast<float>(light.pdf(ref, wi)) : 0.0f, ++i), ...);
                return sum;
            },
            lights_);
    }

    float L(Vector3f ref, Vector3f wi) const {
        return std::apply([&](const auto&... light) { return (0.0f + ... + static_cast<float>(light.L(ref, wi))); },
                          lights_);
    }

    float pmf(std::size_t i) const { return pmf_[i]; }

private:
    void check_pmf() const {
        float sum = 0.0f;
        for (float p : pmf_) {
            if (!(p >= 0.0f) || !std::isfinite(p))
                throw std::invalid_argument("light_set: pmf entries must be finite and >= 0, got " + std::to_string(p));
            sum += p;
        }
        // Float sums of a few entries round by a few 2^-24: 2^-20 leaves room for that, not for a missing light.
        if (!(std::abs(sum - 1.0f) <= 0x1p-20f))
            throw std::invalid_argument("light_set: the pmf sums to " + std::to_string(sum) + ", not 1");
    }

    LightSample sample_light(std::size_t chosen, Vector3f ref, Point2f u) const {
        return sample_light(chosen, ref, u, std::index_sequence_for<Lights...>{});
    }
    template <std::size_t... I>
    LightSample sample_light(std::size_t chosen, Vector3f ref, Point2f u, std::index_sequence<I...>) const {
        LightSample s{};
        ((chosen == I ? (s = std::get<I>(lights_).sample(ref, u), true) : false) || ...);
        return s;
    }

    std::array<float, kCount> pmf_;
    std::tuple<Lights...> lights_;
    bool overlapping_ = false;
};

}  // namespace warpcheck
