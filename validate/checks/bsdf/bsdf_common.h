// What the BSDF checks share: their base class (they take BSDF cases only),
// walking a case's samples chunk by chunk, the integrands their quadratures
// use, and the tally of the delta lobes' samples and claims.
#pragma once

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "chi2/binning.h"
#include "chi2/quadrature.h"
#include "validate/api/bsdf_case.h"
#include "validate/checks/shared/float_probe.h"  // float_neighbours, kFloatStep
#include "validate/checks/check.h"
#include "validate/checks/shared/input_chunks.h"

namespace warpcheck::bsdf {

/// The base of every BSDF check: it takes BSDF cases only (the runner gives it
/// no others), and applies where `bsdf_applicability` says.
class BsdfCheck : public Check {
public:
    bool about_bsdfs() const override { return true; }
    Applicability applicability(const WarpCase& warp) const override {
        const BsdfCase* b = as_bsdf(warp);
        return b ? bsdf_applicability(*b) : Applicability::not_about_such_cases();
    }
    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        return run_bsdf(*as_bsdf(warp), ctx);
    }

protected:
    /// Whether the check runs on a BSDF case (Applicability).
    virtual Applicability bsdf_applicability(const BsdfCase& bsdf) const = 0;
    virtual CheckResult run_bsdf(const BsdfCase& bsdf, const CheckContext& ctx) const = 0;
};

/// Where a check compares a BSDF's values pointwise (f and pdf at a sample's
/// wi, f against a quadrature): it does not apply to a stochastic BSDF
/// (BsdfClaims::stochastic), whose values are estimates; `what` names the
/// comparison, in a few words.
inline Applicability unless_stochastic(const BsdfCase& bsdf, const std::string& what) {
    if (!bsdf.claims().stochastic) return Applicability::runs();
    return Applicability::lacks("a stochastic BSDF: " + what + " are estimates; bsdf_expectation tests them in "
                                "expectation");
}

/// Calls f(chunk, inputs, records) for every chunk of map_input_chunks (edge
/// inputs first when with_edges, then `samples` random ones), with the
/// records of sample_bsdf (valid during the call only); results in chunk order.
template <typename Result, typename F>
std::vector<Result> map_bsdf_chunks(const CheckContext& ctx, const BsdfCase& bsdf, uint64_t samples, bool with_edges,
                                    F&& f) {
    return map_input_chunks<Result>(ctx, InputKind::Uniform3D, samples, with_edges,
                                    [&](std::size_t chunk, std::span<const WarpInput> inputs) {
                                        // Kept per thread: a fresh chunk-sized vector each time costs
                                        // page faults worth a tenth of a cheap BSDF's sampling.
                                        thread_local std::vector<BsdfRecord> records;
                                        records.resize(inputs.size());
                                        bsdf.sample_bsdf(inputs, records);
                                        return f(chunk, inputs, std::span<const BsdfRecord>(records));
                                    });
}

/// The continuous samples' directions among `count` draws from the pilot
/// streams (pilot_inputs: independent of the tested samples), where the
/// sampler puts its mass: equal-probability cells and the cubature's pieces
/// (chi2::refine_by_pilot) are placed by them.
std::vector<std::array<float, 3>> continuous_pilot(const BsdfCase& bsdf, const CheckContext& ctx, std::size_t count);

/// pdf(wo, .) at quadrature nodes.
chi2::BatchPdf pdf_integrand(const BsdfCase& bsdf);
/// f(wo, .) |cos theta_i| at quadrature nodes (p for a phase function), for
/// the given wo (the case's own, or another for a sweep).
chi2::BatchPdf albedo_integrand(const BsdfCase& bsdf, Vector3f wo);

/// This case's point on a plot across its family (FamilyPoint, reports/
/// result.h), at its theta_o: the grid's "theta_o" parameter where it has
/// one, else wo's polar angle in degrees; its curves named by its other
/// parameters ("alpha=0.05"). The caller adds the values and limits.
FamilyPoint family_point(const BsdfCase& bsdf, std::string title, std::string y_label);

/// The cells of the BSDF checks' sphere: the case's chi2_resolution, or by
/// default 32 azimuths by 64 heights, so that each hemisphere has the 32 x 32
/// cells of a hemispherical warp (chi2/binning.h says why about 1000).
chi2::BinResolution bsdf_resolution(const BsdfCase& bsdf);

/// The delta lobes: reflection (0) and transmission (1).
inline constexpr int kDeltaLobes = 2;
/// |a - b| over the larger magnitude, 0 when they differ by at most FLT_MIN (a
/// float value's underflow noise is no disagreement; NaN gives NaN, which no
/// limit accepts).
inline double relative_difference(double a, double b) {
    const double diff = std::abs(a - b);
    if (diff <= FLT_MIN) return 0.0;
    return diff / std::max(std::abs(a), std::abs(b));
}

/// How far a transmitted sample's eta may be from the claimed ratio of
/// indices: 2^-20 relative (eta and 1 / eta are each one float rounding),
/// while a swapped ratio is off by eta^2 - 1 and a wrong medium by percent.
constexpr double kEtaTolerance = 0x1p-20;

/// The eta(wi) / eta(wo) of a transmission through the case's interface.
inline double claimed_eta(const BsdfCase& bsdf) {
    return bsdf.wo().z > 0.0f ? bsdf.claims().eta : 1.0 / bsdf.claims().eta;
}

/// 2^-12 relative, as bsdf_weight's: f(wo, wi) and f(wi, wo) compute the same
/// half vector and Fresnel term from the two directions in another order, each
/// off by a few float roundings, which a sharp lobe's slope (~80 per radian at
/// alpha = 0.05) multiplies to ~1e-5; a non-reciprocal factor is off by percent.
constexpr double kReciprocityTolerance = 0x1p-12;

/// What f(wo, wi) is multiplied by to equal f(wi, wo) under the claimed
/// reciprocity rule (BsdfClaims::reciprocal): 1 for reflection, across the
/// interface (eta(wi) / eta(wo))^2 in radiance transport and its inverse in
/// importance transport. bsdf_reciprocity holds a pair to it pointwise,
/// bsdf_expectation a stochastic f in expectation.
inline double reciprocity_scale(const BsdfCase& bsdf, const WarpOutput& wi) {
    if (!bsdf.transmitted(wi)) return 1.0;
    const double eta = bsdf.claims().eta;
    const double ratio = wi[2] < 0.0f ? eta : 1.0 / eta;  // eta(wi) / eta(wo)
    return bsdf.claims().transport == Transport::Radiance ? ratio * ratio : 1.0 / (ratio * ratio);
}

inline const char* delta_lobe_name(int k) { return k == 0 ? "delta reflection" : "delta transmission"; }

/// The delta samples of a run, per lobe: how many, and what they claim (the
/// probability of choosing the lobe, as their pdf; their weight).
struct DeltaTally {
    struct Lobe {
        uint64_t count = 0;
        double pdf_sum = 0.0;  ///< sum of the claimed probabilities
        double pdf_min = std::numeric_limits<double>::infinity();
        double pdf_max = -std::numeric_limits<double>::infinity();
        double weight_sum = 0.0;  ///< sum of f |cos theta_i| / pdf (energy weights in energy_sum)
        double energy_sum = 0.0;
        void merge(const Lobe& o) {
            count += o.count;
            pdf_sum += o.pdf_sum;
            pdf_min = std::min(pdf_min, o.pdf_min);
            pdf_max = std::max(pdf_max, o.pdf_max);
            weight_sum += o.weight_sum;
            energy_sum += o.energy_sum;
        }
        /// The probability the samples claim: their mean pdf (0 without samples).
        double claimed() const { return count ? pdf_sum / static_cast<double>(count) : 0.0; }
        double mean_weight() const { return count ? weight_sum / static_cast<double>(count) : 0.0; }
        double mean_energy() const { return count ? energy_sum / static_cast<double>(count) : 0.0; }
    };
    std::array<Lobe, kDeltaLobes> lobes{};

    /// The lobe of a delta record (by the side wi is on; a phase function has none).
    static int lobe_of(const BsdfCase& bsdf, const BsdfRecord& r) { return bsdf.transmitted(r.wi) ? 1 : 0; }
    void add(const BsdfCase& bsdf, const BsdfRecord& r) {
        Lobe& l = lobes[static_cast<std::size_t>(lobe_of(bsdf, r))];
        const double pdf = r.pdf, weight = static_cast<double>(r.f) * bsdf.cosine(r.wi) / pdf;
        ++l.count;
        l.pdf_sum += pdf;
        l.pdf_min = std::min(l.pdf_min, pdf);
        l.pdf_max = std::max(l.pdf_max, pdf);
        l.weight_sum += weight;
        l.energy_sum += weight * bsdf.energy_factor(r.wi);
    }
    void merge(const DeltaTally& o) {
        for (int k = 0; k < kDeltaLobes; ++k) lobes[static_cast<std::size_t>(k)].merge(o.lobes[static_cast<std::size_t>(k)]);
    }
    uint64_t count() const { return lobes[0].count + lobes[1].count; }
    /// The total probability of the delta lobes that the samples claim.
    double claimed() const { return lobes[0].claimed() + lobes[1].claimed(); }
};

}  // namespace warpcheck::bsdf
