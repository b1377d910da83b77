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
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sampling/light_sample.h"
#include "validate/api/bsdf_case.h"
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

// ---------------------------------------------------------------------------
// Multiple importance sampling: a BSDF and lights seen from one shading
// point, the strategies a renderer's direct lighting combines. Each strategy
// draws wi with its own sampler; the MIS sum weighs a sample of strategy s by
// the heuristic of the pdf s returned and the other strategies' pdfs at wi, as
// the renderer's MIS code evaluates them (which may be other functions than
// the pdf() each case is checked against: an area-measure pdf, a light's pdf
// without its selection probability). The estimator of the integral of
// f(wo, wi) L(ref, wi) |cos theta_i| is the sum over strategies of
// weight * value / pdf.

/// How the MIS sum weighs a strategy's sample (Veach): the balance heuristic
/// p_s / sum_t p_t, or the power heuristic with exponent 2, p_s^2 / sum_t p_t^2.
enum class MisHeuristic { Balance, Power };

/// The pdfs the renderer's MIS code evaluates at the other strategies'
/// samples, where they are not the cases' own pdf(): each empty one is its
/// case's pdf(). Directions are in the BSDF's shading frame (normal +z), where
/// the lights stand too.
struct MisPdfs {
    /// The BSDF's pdf(wo, wi) as the MIS sum evaluates it at light samples.
    std::function<float(Vector3f wo, Vector3f wi)> bsdf{};
    /// Each light's pdf(ref, wi) as the MIS sum evaluates it at the other
    /// strategies' samples, in the order of the lights; empty or shorter:
    /// the cases' own pdf().
    std::vector<std::function<float(Vector3f ref, Vector3f wi)>> lights{};
    /// The same pdfs in batch form, one call per batch of directions, for a
    /// caller whose every call costs (Python's NumPy functions):
    /// out[i] = the pdf at wi[i], with the BSDF's wo or the light's ref first.
    /// A strategy takes one form or the other, not both; empty: as above.
    using BatchPdf = std::function<void(Vector3f origin, std::span<const WarpOutput> wi, std::span<double> out)>;
    BatchPdf bsdf_batch{};
    std::vector<BatchPdf> lights_batch{};
};

/// What an MIS case declares besides its strategies.
struct MisClaims {
    MisHeuristic heuristic = MisHeuristic::Power;
    MisPdfs pdfs{};
};

/// One strategy's sample as the MIS checks see it: wi, the pdf its sampler
/// returned (0: no sample), and the integrand's value along wi computed with
/// what the sample returned (the BSDF sample's f with L(ref, wi); the light
/// sample's L with f(wo, wi)), |cos theta_i| included.
struct MisRecord {
    WarpOutput wi{};
    float pdf = 0.0f;
    double value = 0.0;
    bool sampled() const { return !(pdf == 0.0f); }
};

/// An MIS case: strategy 0 is the BSDF (a BsdfCase seen from its wo, without
/// delta lobes), strategies 1.. the lights (LightCases seen from one
/// reference point, with the BSDF's normal +z as their normal, or none for a
/// phase function). As a warp it is Veach's one-sample model: u[0] chooses a
/// strategy uniformly (and is reused, rescaled, as the BSDF's uc), and the
/// pdf is the mean of the strategies' MIS pdfs, so chi2 and sample_pdf test
/// the pdfs the MIS sum uses against the densities the samplers draw from.
class MisCase final : public WarpCase {
public:
    /// Refused (std::invalid_argument) where the parts do not fit: not a BSDF
    /// and lights, a delta lobe, lights seen from different points or with
    /// another normal than the BSDF's, more MIS pdfs than lights.
    MisCase(WarpCaseInfo info, MisClaims claims, std::unique_ptr<WarpCase> bsdf,
            std::vector<std::unique_ptr<WarpCase>> lights);

    MisHeuristic heuristic() const { return claims_.heuristic; }
    const BsdfCase& bsdf() const { return *bsdf_; }
    const LightCase& light(std::size_t k) const { return *lights_[k]; }
    std::size_t light_count() const { return lights_.size(); }
    std::size_t strategy_count() const { return 1 + lights_.size(); }
    /// "bsdf", or "light" (with its index where there are several), with the case's name.
    std::string strategy_name(std::size_t s) const;

    /// out[i] = strategy s's sample from in[i] (the BSDF reads uc = u[0] and
    /// u[1], u[2]; a light reads u[0], u[1]).
    void sample_strategy(std::size_t s, std::span<const WarpInput> in, std::span<MisRecord> out) const;
    /// out[i] = strategy s's own pdf() at wi[i]: the density its sample returns.
    void strategy_pdf(std::size_t s, std::span<const WarpOutput> wi, std::span<double> out) const;
    /// Whether the MIS sum evaluates strategy s with a pdf of its own (MisPdfs).
    bool has_mis_pdf(std::size_t s) const;
    /// out[i] = strategy s's pdf at wi[i] as the MIS sum evaluates it.
    void mis_pdf(std::size_t s, std::span<const WarpOutput> wi, std::span<double> out) const;
    /// out[i] = f(wo, wi) L(ref, wi) |cos theta_i|, L summed over the lights
    /// (their own intersections), from the cases' functions.
    void integrand(std::span<const WarpOutput> wi, std::span<double> out) const;
    /// The heuristic's weight of a sample whose strategy's pdf is `own`
    /// beside the other strategies' pdfs `others`: 1 where all are 0 but own.
    double weight(double own, std::span<const double> others) const;

    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override;
    void sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                           std::span<double> value) const override;
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override;
    void invert(std::span<const WarpOutput>, std::span<WarpInput>) const override {
        throw std::logic_error("an MIS case has no inverse");
    }

private:
    /// The strategy u[0] chooses, and the input it passes on.
    std::size_t choose(const WarpInput& in, WarpInput& passed) const;
    /// Each sample of the one-sample model with its strategy's record.
    void sample_mixture(std::span<const WarpInput> in, std::span<MisRecord> out, std::span<std::size_t> strategy) const;

    MisClaims claims_;
    std::unique_ptr<WarpCase> bsdf_owner_;
    std::vector<std::unique_ptr<WarpCase>> light_owners_;
    const BsdfCase* bsdf_ = nullptr;
    std::vector<const LightCase*> lights_;
};

/// Makes an MIS case of a BSDF case (make_bsdf_case) and one or more light
/// cases (make_light_case) seen from the same shading point, their strategy
/// names being their case names. Refused where the parts do not fit.
std::unique_ptr<WarpCase> make_mis_case(WarpCaseInfo info, MisClaims claims, std::unique_ptr<WarpCase> bsdf,
                                        std::vector<std::unique_ptr<WarpCase>> lights);
/// The same with one light.
std::unique_ptr<WarpCase> make_mis_case(WarpCaseInfo info, MisClaims claims, std::unique_ptr<WarpCase> bsdf,
                                        std::unique_ptr<WarpCase> light);

/// The MIS case inside a WarpCase, or nullptr.
inline const MisCase* as_mis(const WarpCase& warp) { return dynamic_cast<const MisCase*>(&warp); }

/// Whether a case may decline to sample (a sample of pdf 0, as pbrt's
/// SampleLi returns none): a light or an MIS case. Such a sample is counted,
/// not judged, by the checks that judge each sample's direction.
inline bool declines_samples(const WarpCase& warp) { return as_light(warp) != nullptr || as_mis(warp) != nullptr; }

}  // namespace warpcheck
