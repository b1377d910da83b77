// A light case: a renderer's light as it is, seen from one reference point
// (and the normal of the surface there), with a stable name such as
// sphere_light[radius=0.1,distance=4,theta=60]. Its parts are the ones a
// renderer's light sampler has (sampling/light.h has the built-in ones):
// sample(ref, u) -> LightSample (sampling/light_sample.h)
// (wi, pdf in solid angle, the radiance L arriving along wi, distance),
// pdf(ref, wi) and the light's own L(ref, wi): its intersection seen from the
// other side, L > 0 where a ray from ref along wi hits it, 0 where it misses.
//
// Seen from its reference point a light is a warp on the sphere of directions
// that returns its pdf, so every warp check that takes such a warp runs on it
// (chi2, unbinned, consistency, sample_pdf, and roundtrip where it has an
// inverse); the light checks (validate/checks/light/light_checks.h) test what
// only a light has: L against the light's own intersection, the support from
// both sides, and the irradiance estimator's mean.
#pragma once

#include <cmath>
#include <concepts>
#include <memory>
#include <span>
#include <stdexcept>
#include <utility>

#include "sampling/light_sample.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

/// Where a light case is seen from.
struct LightClaims {
    Vector3f ref{};  ///< the reference point
    /// The unit normal of the reference surface, which weighs the irradiance
    /// by |cos theta_i| and tells which samples lie behind the surface; zero:
    /// a point in a medium (no cosine, nothing behind).
    Vector3f normal{};
};

/// One light sample as the checks see it: the LightSample, with wi as a WarpOutput.
struct LightRecord {
    WarpOutput wi{};
    float pdf = 0.0f;
    float L = 0.0f;
    float distance = 0.0f;
    /// Whether there is a sample: pdf != 0 (a NaN pdf is a sample, and fails).
    bool sampled() const { return !(pdf == 0.0f); }
};

class LightCase : public WarpCase {
public:
    /// Sets info.domain to the sphere; the input is Uniform2D and sample
    /// returns its pdf. The claims are checked with the rest of the
    /// declaration: ref finite, the normal zero or of unit length.
    LightCase(WarpCaseInfo info, LightClaims claims, bool has_inverse);

    const LightClaims& claims() const { return claims_; }
    Vector3f ref() const { return claims_.ref; }
    /// Whether the reference point lies on a surface (a normal is given).
    bool on_surface() const { return !(claims_.normal == Vector3f{}); }

    /// out[i] = sample(ref, u = (in[i].u[0], in[i].u[1])).
    virtual void sample_light(std::span<const WarpInput> in, std::span<LightRecord> out) const = 0;
    /// out[i] = L(ref, wi[i]), the radiance the light's own intersection finds along wi.
    virtual void radiance(std::span<const WarpOutput> wi, std::span<double> out) const = 0;

    /// The factor of L in the irradiance: |cos theta_i| against the surface's
    /// normal, or 1 for a point in a medium.
    double cosine(const WarpOutput& wi) const {
        if (!on_surface()) return 1.0;
        return std::abs(static_cast<double>(wi[0]) * claims_.normal.x + static_cast<double>(wi[1]) * claims_.normal.y +
                        static_cast<double>(wi[2]) * claims_.normal.z);
    }
    /// Whether wi points below the reference surface (never for a point in a medium).
    bool behind_surface(const WarpOutput& wi) const {
        return on_surface() && static_cast<double>(wi[0]) * claims_.normal.x +
                                       static_cast<double>(wi[1]) * claims_.normal.y +
                                       static_cast<double>(wi[2]) * claims_.normal.z <
                                   0.0;
    }

    /// The direction of each sample; a missing sample (pdf 0) is NaN, which the
    /// consistency check reports as a sample outside the domain.
    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override;
    /// The direction and the pdf that sample returned with it.
    void sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                           std::span<double> value) const override;

private:
    LightClaims claims_;
};

/// A light object: const members sample(Vector3f ref, Point2f u) -> LightSample,
/// pdf(Vector3f ref, Vector3f wi) and L(Vector3f ref, Vector3f wi) (float or
/// double), and invert(Vector3f ref, Vector3f wi) -> Point2f where it has one,
/// as the lights of sampling/light.h have.
template <typename L>
concept LightObject = requires(const L& light, Vector3f w, Point2f u) {
    { light.sample(w, u) } -> std::convertible_to<LightSample>;
    light.pdf(w, w);
    light.L(w, w);
};

namespace detail {

/// A light case around a light object, whose members are called directly.
template <LightObject Light>
class ObjectLightCase final : public LightCase {
public:
    static constexpr bool kHasInverse = requires(const Light& l, Vector3f w) {
        { l.invert(w, w) } -> std::convertible_to<Point2f>;
    };

    ObjectLightCase(WarpCaseInfo info, LightClaims claims, Light light)
        : LightCase(std::move(info), claims, kHasInverse), light_(std::move(light)) {}

    void sample_light(std::span<const WarpInput> in, std::span<LightRecord> out) const override {
        const Vector3f p = ref();
        for (std::size_t k = 0; k < in.size(); ++k) {
            const LightSample s = light_.sample(p, Point2f{in[k].u[0], in[k].u[1]});
            out[k] = {{s.wi.x, s.wi.y, s.wi.z}, s.pdf, s.L, s.distance};
        }
    }
    void radiance(std::span<const WarpOutput> wi, std::span<double> out) const override {
        const Vector3f p = ref();
        for (std::size_t k = 0; k < wi.size(); ++k)
            out[k] = static_cast<double>(light_.L(p, Vector3f{wi[k][0], wi[k][1], wi[k][2]}));
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override {
        const Vector3f p = ref();
        for (std::size_t k = 0; k < x.size(); ++k)
            out[k] = static_cast<double>(light_.pdf(p, Vector3f{x[k][0], x[k][1], x[k][2]}));
    }
    void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const override {
        if constexpr (kHasInverse) {
            const Vector3f p = ref();
            for (std::size_t k = 0; k < x.size(); ++k) {
                const Point2f u = light_.invert(p, Vector3f{x[k][0], x[k][1], x[k][2]});
                out[k] = WarpInput{{u.x, u.y, 0.0f}, 0};
            }
        } else {
            (void)x, (void)out;
            throw std::logic_error("light case " + name() + " has no inverse");
        }
    }

private:
    Light light_;
};

}  // namespace detail

/// Makes a light case from a light object seen from claims.ref (and the
/// surface's normal there). Refused where the declaration contradicts itself.
template <LightObject Light>
std::unique_ptr<WarpCase> make_light_case(WarpCaseInfo info, LightClaims claims, Light light) {
    auto light_case = std::make_unique<detail::ObjectLightCase<Light>>(std::move(info), claims, std::move(light));
    validate_case(*light_case);
    return light_case;
}

/// The light case inside a WarpCase, or nullptr.
inline const LightCase* as_light(const WarpCase& warp) { return dynamic_cast<const LightCase*>(&warp); }

}  // namespace warpcheck
