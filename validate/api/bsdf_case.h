// A BSDF case: a renderer's BSDF (or phase function) as it is, at one outgoing
// direction wo, with a stable name such as rough_conductor[alpha=0.3,theta_o=60].
// Its parts are pbrt-v4's (sampling/bsdf.h): sample(wo, uc, u) -> BsdfSample
// (wi, f, pdf, flags, eta), f(wo, wi) and pdf(wo, wi); a phase function's are
// sample(wo, u), p(wo, wi) and pdf(wo, wi). Each is a claim that a BSDF check
// tests (validate/checks/bsdf/bsdf_checks.h); only those checks take BSDF cases.
//
// The domain is the whole sphere of wi, reflection and transmission together,
// whatever the lobes; the input is (uc, u.x, u.y) in [0,1)^3 (InputKind::Uniform3D,
// uc in u[0]), drawn like any other input from the (case, check) stream.
#pragma once

#include <array>
#include <cmath>
#include <concepts>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "sampling/bsdf.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

/// What a BSDF case declares besides its functions.
struct BsdfClaims {
    Vector3f wo{0.0f, 0.0f, 1.0f};  ///< the outgoing direction of the case, unit length
    /// The lobes it may sample (sampling/bsdf.h): Continuous for a density,
    /// Delta for delta lobes, and Reflection and/or Transmission.
    BsdfFlags lobes = BsdfFlags::None;
    /// Whether f is reciprocal: f(wo, wi) = f(wi, wo) for reflection, and
    /// across the interface f(wo, wi) / eta(wo)^2 = f(wi, wo) / eta(wi)^2
    /// (Transport::Radiance) or f(wo, wi) / eta(wi)^2 = f(wi, wo) / eta(wo)^2
    /// (Transport::Importance), eta(w) being the index on w's side.
    bool reciprocal = true;
    Transport transport = Transport::Radiance;
    /// The index of refraction below the surface over above (1 without transmission).
    float eta = 1.0f;
    /// A phase function: wi on the whole sphere, weight p / pdf (no cosine).
    bool phase_function = false;
    /// A stochastic BSDF (a layered one, pbrt-v4's LayeredBxDF): f(wo, wi) is
    /// an unbiased estimate of the BSDF (a one-sample random walk), a sample's
    /// f |cos theta_i| / pdf an unbiased estimate of its throughput whose pdf
    /// is only proportional to the density it was drawn from
    /// (pdfIsProportional), and pdf(wo, wi) an approximation kept for multiple
    /// importance sampling. The checks that compare values pointwise (the
    /// weight identity, the chi-square and unbinned tests against pdf(),
    /// reciprocity, the albedo by quadrature) do not apply;
    /// bsdf_expectation tests it in expectation, per cell of the sphere:
    /// the weights against f, and f(wo, wi) against f(wi, wo) where
    /// `reciprocal` is claimed.
    bool stochastic = false;
};

/// One sample as the checks see it: the BsdfSample, with wi as a WarpOutput.
struct BsdfRecord {
    WarpOutput wi{};
    float f = 0.0f;
    float pdf = 0.0f;
    float eta = 1.0f;
    BsdfFlags flags = BsdfFlags::None;
    /// Whether there is a sample: pdf != 0 (a NaN pdf is a sample, and fails).
    bool sampled() const { return !(pdf == 0.0f); }
    bool delta() const { return has(flags, BsdfFlags::Delta); }
};

/// The unit direction at polar angle theta and azimuth phi, both in degrees,
/// computed in double and rounded to float.
Vector3f bsdf_direction(double theta_degrees, double phi_degrees = 0.0);

class BsdfCase : public WarpCase {
public:
    /// Sets info.domain to the sphere; its input is Uniform3D (uc, u). The
    /// claims are checked with the rest of the declaration (validate_case):
    /// wo must be a finite unit vector off the horizon, and there must be lobes.
    BsdfCase(WarpCaseInfo info, BsdfClaims claims);

    const BsdfClaims& claims() const { return claims_; }
    Vector3f wo() const { return claims_.wo; }
    bool phase_function() const { return claims_.phase_function; }

    /// out[i] = sample(wo, uc = in[i].u[0], u = (in[i].u[1], in[i].u[2])).
    virtual void sample_bsdf(std::span<const WarpInput> in, std::span<BsdfRecord> out) const = 0;
    /// out[i] = f(a[i], b[i]) (p for a phase function), for any pair: the
    /// reciprocity check swaps the arguments.
    virtual void f(std::span<const WarpOutput> a, std::span<const WarpOutput> b, std::span<double> out) const = 0;

    /// out[i] = f(wo, wi[i]) |cos theta_i| (p for a phase function): the
    /// integrand whose integral over the sphere is the directional albedo.
    void f_cos(std::span<const WarpOutput> wi, std::span<double> out) const;
    /// The factor of f in the weight: |cos theta_i|, or 1 for a phase function.
    double cosine(const WarpOutput& wi) const { return phase_function() ? 1.0 : std::abs(static_cast<double>(wi[2])); }
    /// Whether wi lies across the surface from wo (a transmitted direction).
    bool transmitted(const WarpOutput& wi) const {
        return !phase_function() && static_cast<double>(wi[2]) * claims_.wo.z < 0.0;
    }
    /// What turns f |cos theta_i| into energy: (eta(wi) / eta(wo))^2 for a
    /// transmitted direction in radiance transport (undoing the 1 / etap^2 that
    /// is radiance's compression, not a gain), else 1. The energy albedo, the
    /// integral of f |cos theta_i| times this, is at most 1 for a passive surface.
    double energy_factor(const WarpOutput& wi) const;

    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override;
    void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const override;

private:
    BsdfClaims claims_;
};

/// A BSDF given as callables, each part named, so that f and pdf (of one type)
/// cannot take each other's place: bsdf_of(sample).with_f(f).with_pdf(pdf),
/// with sample(Vector3f wo, float uc, Point2f u) -> BsdfSample (a phase
/// function's sample(Vector3f wo, Point2f u)), f(Vector3f wo, Vector3f wi) and
/// pdf(Vector3f wo, Vector3f wi) -> float or double.
template <typename Sample, typename F = detail::NotGiven, typename Pdf = detail::NotGiven>
struct CallableBsdf {
    Sample sample;
    F f{};
    Pdf pdf{};

    /// This BSDF with `g` as its f(wo, wi).
    template <typename G>
    CallableBsdf<Sample, G, Pdf> with_f(G g) const {
        static_assert(std::is_same_v<F, detail::NotGiven>, "f is given twice");
        return {sample, std::move(g), pdf};
    }
    /// This BSDF with `g` as its pdf(wo, wi).
    template <typename G>
    CallableBsdf<Sample, F, G> with_pdf(G g) const {
        static_assert(std::is_same_v<Pdf, detail::NotGiven>, "the pdf is given twice");
        return {sample, f, std::move(g)};
    }
};

/// A BSDF of callables whose sample is `sample` (CallableBsdf).
template <typename Sample>
CallableBsdf<Sample> bsdf_of(Sample sample) {
    return {std::move(sample)};
}

/// A BSDF object: const members sample(Vector3f, float, Point2f) -> BsdfSample
/// (a phase function's sample(Vector3f, Point2f)), f(Vector3f, Vector3f) (a
/// phase function's p) and pdf(Vector3f, Vector3f), as the BSDFs of
/// sampling/bsdf_*.h have, and flags() -> BsdfFlags, eta() and transport()
/// where it has them; or a CallableBsdf (bsdf_of).
template <typename B>
concept BsdfObject = requires(const B& b, Vector3f w, float uc, Point2f u) {
    requires(requires { { b.sample(w, uc, u) } -> std::convertible_to<BsdfSample>; } ||
             requires { { b.sample(w, u) } -> std::convertible_to<BsdfSample>; });
    requires(requires { b.f(w, w); } || requires { b.p(w, w); });
    b.pdf(w, w);
};

namespace detail {

inline Vector3f to_vector(const WarpOutput& o) { return {o[0], o[1], o[2]}; }
inline WarpOutput to_output_of(const Vector3f& v) { return {v.x, v.y, v.z}; }

/// A BSDF case around a BSDF object, whose members are called directly, so
/// that they inline into the batch loops.
template <BsdfObject B>
class ObjectBsdfCase final : public BsdfCase {
public:
    ObjectBsdfCase(WarpCaseInfo info, BsdfClaims claims, B bsdf)
        : BsdfCase(std::move(info), claims), bsdf_(std::move(bsdf)) {}

    void sample_bsdf(std::span<const WarpInput> in, std::span<BsdfRecord> out) const override {
        const Vector3f wo = this->wo();
        for (std::size_t k = 0; k < in.size(); ++k) {
            const BsdfSample s = call_sample(wo, in[k]);
            out[k] = {to_output_of(s.wi), s.f, s.pdf, s.eta, s.flags};
        }
    }
    void f(std::span<const WarpOutput> a, std::span<const WarpOutput> b, std::span<double> out) const override {
        for (std::size_t k = 0; k < a.size(); ++k) out[k] = call_f(to_vector(a[k]), to_vector(b[k]));
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override {
        const Vector3f wo = this->wo();
        for (std::size_t k = 0; k < x.size(); ++k) out[k] = static_cast<double>(bsdf_.pdf(wo, to_vector(x[k])));
    }

private:
    BsdfSample call_sample(Vector3f wo, const WarpInput& in) const {
        if constexpr (requires { bsdf_.sample(wo, in.u[0], Point2f{}); })
            return bsdf_.sample(wo, in.u[0], Point2f{in.u[1], in.u[2]});
        else
            return bsdf_.sample(wo, Point2f{in.u[1], in.u[2]});
    }
    double call_f(Vector3f wo, Vector3f wi) const {
        if constexpr (requires { bsdf_.f(wo, wi); }) return static_cast<double>(bsdf_.f(wo, wi));
        else return static_cast<double>(bsdf_.p(wo, wi));
    }

    B bsdf_;
};

}  // namespace detail

/// Makes a BSDF case from a BSDF object (or a CallableBsdf) seen from
/// claims.wo: the lobes come from its flags(), eta and transport from its
/// eta() and transport() when it has them; otherwise, and for the rest of the
/// claims (reciprocity), as given. Refused where the declaration contradicts
/// itself (validate_case).
template <BsdfObject B>
std::unique_ptr<WarpCase> make_bsdf_case(WarpCaseInfo info, BsdfClaims claims, B bsdf) {
    if constexpr (requires { bsdf.flags(); }) claims.lobes = bsdf.flags();
    if constexpr (requires { bsdf.eta(); }) claims.eta = bsdf.eta();
    if constexpr (requires { bsdf.transport(); }) claims.transport = bsdf.transport();
    auto bsdf_case = std::make_unique<detail::ObjectBsdfCase<B>>(std::move(info), claims, std::move(bsdf));
    validate_case(*bsdf_case);
    return bsdf_case;
}

/// A phase-function object: sample(Vector3f, Point2f) -> BsdfSample, p and pdf.
template <typename P>
concept PhaseObject = requires(const P& p, Vector3f w, Point2f u) {
    { p.sample(w, u) } -> std::convertible_to<BsdfSample>;
    p.p(w, w);
    p.pdf(w, w);
};

/// Makes a phase function's case seen from wo (reciprocal, one continuous lobe).
template <PhaseObject P>
std::unique_ptr<WarpCase> make_phase_case(WarpCaseInfo info, Vector3f wo, P phase) {
    return make_bsdf_case(std::move(info), {.wo = wo, .lobes = BsdfFlags::Continuous, .phase_function = true},
                          std::move(phase));
}

/// The BSDF case inside a WarpCase, or nullptr.
inline const BsdfCase* as_bsdf(const WarpCase& warp) { return dynamic_cast<const BsdfCase*>(&warp); }

// ---------------------------------------------------------------------------
// Spectral BSDFs: f per channel (RGB, or N wavelengths sampled with a hero),
// their samples a SpectralSample<N> (sampling/bsdf.h).

/// A spectral BSDF object: const members sample(Vector3f wo, float uc,
/// Point2f u, int hero) -> SpectralSample<N>, f(Vector3f, Vector3f) and
/// pdf(Vector3f, Vector3f) -> std::array<float, N> (every channel's), and
/// flags(); eta(int channel) where it transmits; and, optionally, one
/// channel's f(wo, wi, channel) and pdf(wo, wi, channel), and
/// sample_hero(wo, uc, u, hero) -> BsdfSample (sample()'s hero channel alone),
/// which the checks of a channel case then call instead (a third of the work
/// with three channels; bsdf_spectral holds sample_hero to sample()).
template <typename B>
concept SpectralBsdfObject = requires(const B& b, Vector3f w, float uc, Point2f u, int hero) {
    b.sample(w, uc, u, hero);
    { b.f(w, w).size() } -> std::convertible_to<std::size_t>;
    { b.pdf(w, w).size() } -> std::convertible_to<std::size_t>;
    { b.flags() } -> std::convertible_to<BsdfFlags>;
};

/// What the check bsdf_spectral sees of a channel case of a spectral BSDF
/// (make_spectral_bsdf_case): its channel count and hero, and every channel's
/// sampled and recomputed values.
class SpectralChannels {
public:
    virtual ~SpectralChannels() = default;
    virtual int channels() const = 0;
    virtual int hero() const = 0;
    /// For each input, the sample's wi and its f and pdf in every channel
    /// (f[i * channels() + c]).
    virtual void sample_all(std::span<const WarpInput> in, std::span<WarpOutput> wi, std::span<float> f,
                            std::span<float> pdf, std::span<BsdfFlags> flags) const = 0;
    /// f(wo, wi) and pdf(wo, wi) in every channel at one wi.
    virtual void values_all(const WarpOutput& wi, std::span<float> f, std::span<float> pdf) const = 0;
};

namespace detail {

/// One channel of a spectral BSDF as a BSDF case: its sampler draws with this
/// channel as the hero, its f and pdf are this channel's; every BSDF check
/// runs on it as on any BSDF, and bsdf_spectral on the other channels' values.
template <SpectralBsdfObject B>
class SpectralChannelCase final : public BsdfCase, public SpectralChannels {
public:
    static constexpr std::size_t kN = std::tuple_size_v<std::remove_cvref_t<decltype(std::declval<const B&>().f(
        Vector3f{}, Vector3f{}))>>;

    SpectralChannelCase(WarpCaseInfo info, BsdfClaims claims, B bsdf, int hero)
        : BsdfCase(std::move(info), claims), bsdf_(std::move(bsdf)), hero_(hero) {}

    int channels() const override { return static_cast<int>(kN); }
    int hero() const override { return hero_; }

    void sample_bsdf(std::span<const WarpInput> in, std::span<BsdfRecord> out) const override {
        const Vector3f wo = this->wo();
        const auto h = static_cast<std::size_t>(hero_);
        for (std::size_t k = 0; k < in.size(); ++k) {
            const Point2f u{in[k].u[1], in[k].u[2]};
            if constexpr (requires { { bsdf_.sample_hero(wo, in[k].u[0], u, hero_) } -> std::convertible_to<BsdfSample>; }) {
                const BsdfSample s = bsdf_.sample_hero(wo, in[k].u[0], u, hero_);
                out[k] = {to_output_of(s.wi), s.f, s.pdf, s.eta, s.flags};
            } else {
                const auto s = bsdf_.sample(wo, in[k].u[0], u, hero_);
                out[k] = {to_output_of(s.wi), s.f[h], s.pdf[h], s.eta, s.flags};
            }
        }
    }
    void f(std::span<const WarpOutput> a, std::span<const WarpOutput> b, std::span<double> out) const override {
        for (std::size_t k = 0; k < a.size(); ++k) out[k] = static_cast<double>(f_of(to_vector(a[k]), to_vector(b[k])));
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override {
        const Vector3f wo = this->wo();
        for (std::size_t k = 0; k < x.size(); ++k) out[k] = static_cast<double>(pdf_of(wo, to_vector(x[k])));
    }
    void sample_all(std::span<const WarpInput> in, std::span<WarpOutput> wi, std::span<float> f, std::span<float> pdf,
                    std::span<BsdfFlags> flags) const override {
        const Vector3f wo = this->wo();
        for (std::size_t k = 0; k < in.size(); ++k) {
            const auto s = bsdf_.sample(wo, in[k].u[0], Point2f{in[k].u[1], in[k].u[2]}, hero_);
            wi[k] = to_output_of(s.wi);
            flags[k] = s.flags;
            for (std::size_t c = 0; c < kN; ++c) f[k * kN + c] = s.f[c], pdf[k * kN + c] = s.pdf[c];
        }
    }
    void values_all(const WarpOutput& wi, std::span<float> f, std::span<float> pdf) const override {
        const auto fv = bsdf_.f(this->wo(), to_vector(wi));
        const auto pv = bsdf_.pdf(this->wo(), to_vector(wi));
        for (std::size_t c = 0; c < kN; ++c) f[c] = fv[c], pdf[c] = pv[c];
    }

private:
    /// The hero channel's f and pdf: by the object's f(wo, wi, channel) and
    /// pdf(wo, wi, channel) where it has them (one channel's work), else the
    /// hero's entry of every channel's.
    float f_of(Vector3f a, Vector3f b) const {
        if constexpr (requires { bsdf_.f(a, b, hero_); }) return bsdf_.f(a, b, hero_);
        else return bsdf_.f(a, b)[static_cast<std::size_t>(hero_)];
    }
    float pdf_of(Vector3f wo, Vector3f wi) const {
        if constexpr (requires { bsdf_.pdf(wo, wi, hero_); }) return bsdf_.pdf(wo, wi, hero_);
        else return bsdf_.pdf(wo, wi)[static_cast<std::size_t>(hero_)];
    }

    B bsdf_;
    int hero_;
};

}  // namespace detail

/// The case of one channel of a spectral BSDF, `hero` in [0, N): named with
/// the parameter hero = that channel (add it to info.params, or make it a
/// grid axis), its lobes from flags(), its eta from eta(hero) where the
/// object has one. Every BSDF check runs on it with this channel's f and
/// pdf, and bsdf_spectral checks the other channels' values at its samples.
template <SpectralBsdfObject B>
std::unique_ptr<WarpCase> make_spectral_bsdf_case(WarpCaseInfo info, BsdfClaims claims, B bsdf, int hero) {
    using Case = detail::SpectralChannelCase<B>;
    if (!(hero >= 0 && hero < static_cast<int>(Case::kN)))
        throw std::invalid_argument("make_spectral_bsdf_case: hero " + std::to_string(hero) + " is not a channel of " +
                                    std::to_string(Case::kN));
    claims.lobes = bsdf.flags();
    if constexpr (requires { bsdf.eta(hero); }) claims.eta = bsdf.eta(hero);
    auto c = std::make_unique<Case>(std::move(info), claims, std::move(bsdf), hero);
    validate_case(*c);
    return c;
}

/// The spectral view of a case, or nullptr.
inline const SpectralChannels* as_spectral(const WarpCase& warp) {
    return dynamic_cast<const SpectralChannels*>(&warp);
}

}  // namespace warpcheck
