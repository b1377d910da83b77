// "light_irradiance": the estimator a renderer forms from a light sample,
// L |cos theta_i| / pdf with the values sample returned (0 where it gave no
// sample), has the integral of L(ref, w) |cos theta_i| over the sphere as its
// mean (irradiance at a surface; without a normal, the integral of L). A pdf
// off by a factor on part of the light, an area pdf left unconverted, or an L
// that differs from the light's own biases it. Statistical: a t-test of the
// mean in the run's multiple-testing family, which needs a finite variance,
// E[(L cos / pdf)^2] finite: true where the pdf stays away from 0 on the light.
//
// The reference integrates L |cos| over the sphere on cells that tile it
// (verified, with the light's float noise): kIrradianceCells uniform cells,
// or, where a pilot of the sampler fills under a quarter of them (a small
// light), as many cells of equal pilot probability (chi2's rule), so that a
// light 1e-3 rad across is integrated on hundreds of cells instead of inside
// one; then again on pieces the pilot places where its points cluster
// (chi2::refine_by_pilot). The cells cover the whole sphere, so lit regions
// the sampler misses are integrated too, on the cells around them; what the
// nodes of a large cell step over, a lit region the sampler never draws,
// light_support reports where it probes.
#include <cmath>
#include <vector>

#include <boost/math/distributions/normal.hpp>
#include <fmt/format.h>

#include "chi2/binning.h"
#include "chi2/chi2_test.h"
#include "chi2/equal_probability.h"
#include "chi2/mean_test.h"
#include "chi2/quadrature.h"
#include "validate/api/light_case.h"
#include "validate/checks/cell_evidence.h"
#include "validate/checks/evidence.h"
#include "validate/checks/input_chunks.h"
#include "validate/checks/light/light_checks.h"
#include "validate/checks/light/light_pilot.h"
#include "validate/checks/power_level.h"

namespace warpcheck::light {
namespace {

/// The rounding allowance of the reference, relative, as for weight_mean: the
/// float L cos / pdf of every sample may be off by a few ulps in the same
/// direction, biasing the mean of 10^6 by up to ~16 ulps (2^-20).
constexpr double kRoundingAllowance = 0x1p-20;
/// The uniform cells of the reference's cubature, as bsdf_albedo's.
constexpr chi2::BinResolution kIrradianceCells{16, 32};
/// The effect every row states its power against: a bias of 1% of the
/// irradiance, what a renderer's user sees as a wrong exposure; a row whose
/// test detects it less than 90% of the time is weak.
constexpr double kStatedBias = 0.01;

/// The relative bias of the mean the two-sided t-test detects 90% of the
/// time at the level of a typical run: (z_{1 - level/2} + z_{0.9}) standard
/// errors over the reference.
double bias_for_power(const CheckContext& ctx, const chi2::MeanTest& t) {
    const boost::math::normal z;
    const double level = power_level(ctx.options(), 1);
    const double k = boost::math::quantile(boost::math::complement(z, 0.5 * level)) +
                     boost::math::quantile(z, 0.9);
    return k * t.standard_error / std::abs(t.reference);
}

struct Estimates {
    chi2::Moments moments;
    uint64_t invalid = 0;
    void merge(const Estimates& o) {
        moments.merge(o.moments);
        invalid += o.invalid;
    }
};

Estimates estimate(const LightCase& light, const CheckContext& ctx) {
    auto parts = map_input_chunks<Estimates>(ctx, InputKind::Uniform2D, ctx.options().samples, false,
                                             [&](std::size_t, std::span<const WarpInput> inputs) {
        std::vector<LightRecord> rec(inputs.size());
        light.sample_light(inputs, rec);
        Estimates e;
        for (const LightRecord& r : rec) {
            const double v = r.sampled() ? static_cast<double>(r.L) * light.cosine(r.wi) / r.pdf : 0.0;
            if (!std::isfinite(v)) ++e.invalid;
            else e.moments.add(v);
        }
        return e;
    });
    return merge_in_order(parts);
}

struct Reference {
    double value = 0.0, error = 0.0, float_noise = 0.0;
    uint64_t evaluations = 0;
    chi2::PilotRefinement refinement;
};

Reference integrate(const LightCase& light, const CheckContext& ctx) {
    const chi2::Binning grid(light.domain(), kIrradianceCells);
    const std::size_t pilot_count = chi2::kPilotPointsPerCell * grid.cell_count();
    std::vector<chi2::SamplePoint> pilot;
    double pilot_sum = 0.0;  // over the pilot's inputs: a declined sample adds 0
    for (const LightRecord& r : light_pilot(light, ctx, pilot_count)) {
        pilot.push_back(r.wi);
        pilot_sum += static_cast<double>(r.L) * light.cosine(r.wi) / r.pdf;
    }
    // The quadrature's accuracy rule is absolute, sized for a density whose
    // integral is 1: the integrand is divided by the pilot's estimate of the
    // integral (a light 1e-3 rad across has an irradiance of 1e-5), so that
    // its error is held relative to the integral.
    const double pilot_mean = pilot_sum / static_cast<double>(pilot_count);
    const double scale = std::isfinite(pilot_mean) && pilot_mean > 0.0 ? pilot_mean : 1.0;
    chi2::EqualProbabilityCells cells;
    if (!pilot.empty() &&
        chi2::effective_cells(grid, pilot) < chi2::kMinEffectiveCellShare * static_cast<double>(grid.cell_count()))
        cells = chi2::equal_probability_cells(grid, pilot, ctx.options().samples);
    const chi2::Binning binning =
        cells.edges.empty() ? grid : chi2::Binning(light.domain(), grid.resolution(), cells.edges);
    const chi2::BatchPdf integrand = [&light, scale](std::span<const chi2::DomainPoint> points,
                                                     std::span<double> out) {
        std::vector<WarpOutput> x(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) x[i] = to_warp_output(points[i]);
        light.radiance(x, out);
        for (std::size_t i = 0; i < x.size(); ++i) out[i] *= light.cosine(x[i]) / scale;
    };
    chi2::QuadratureOptions q;
    q.sample_count = ctx.options().samples;
    q.verify = true;
    q.float_noise = true;
    chi2::CellIntegrals c = chi2::integrate_cells(binning, integrand, q, ctx.executor());
    chi2::PilotRefinement refined = chi2::refine_by_pilot(binning, pilot, integrand, q, c, ctx.executor());
    refined.missed_mass *= scale;
    return {c.total * scale, c.error_total * scale, c.float_noise_total * scale, c.evaluations, refined};
}

class LightIrradianceCheck final : public Check {
public:
    std::string name() const override { return "light_irradiance"; }
    bool statistical() const override { return true; }
    std::string description() const override {
        return "light: the mean of L |cos| / pdf against the integral of L(ref, w) |cos| over the sphere (t-test, "
               "Sidak-corrected)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        return Applicability::when(as_light(warp) != nullptr);
    }
    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const LightCase& light = *as_light(warp);
        const Estimates e = estimate(light, ctx);
        const Reference ref = integrate(light, ctx);
        // The reference's uncertainty: its verified bound, its float noise
        // and the estimator's rounding, each independent of the others.
        const double uncertainty =
            std::hypot(ref.error, ref.float_noise, kRoundingAllowance * std::abs(ref.value));
        const chi2::MeanTest t = chi2::mean_test(e.moments, ref.value, uncertainty);
        CheckResult r;
        r.samples = e.moments.n + e.invalid;
        r.figures = {{"samples", static_cast<double>(r.samples)},
                     {"mean", t.mean},
                     {"reference", ref.value},
                     {"reference_error", ref.error},
                     {"reference_float_noise", ref.float_noise},
                     {"standard_error", t.standard_error},
                     {"t", t.t},
                     {"p_value", t.p_value},
                     {"invalid_samples", static_cast<double>(e.invalid)},
                     {"evaluations", static_cast<double>(ref.evaluations)}};
        add_pilot_refinement_figures(r.figures, ref.refinement);
        const double power_bias = bias_for_power(ctx, t);
        r.figures.push_back({"power_relative_bias", power_bias});
        r.p_value = t.p_value;
        r.verdict = Verdict::Pass;
        const char* what = light.on_surface() ? "irradiance" : "integral of L";
        r.summary = fmt::format("{} {:.6g} vs {:.6g} (t = {:.2f}); 90% power: bias {:.2g}%", what, t.mean,
                                t.reference, t.t, 100.0 * power_bias);
        if (!(power_bias <= kStatedBias))
            r.weak = fmt::format("cannot see a {:.0f}% bias of the {} (90% power only at {:.2g}%): {}",
                                 100.0 * kStatedBias, what, 100.0 * power_bias,
                                 uncertainty > t.standard_error / std::sqrt(2.0)
                                     ? "the integral's own bound is most of the uncertainty"
                                     : "more samples would");
        if (e.invalid > 0) {
            r.verdict = Verdict::Fail;
            r.summary = fmt::format("{} of {} estimates not finite", e.invalid, r.samples);
            r.message = r.summary + " (L cos / pdf: a pdf of 0 or NaN with light, or a non-finite L)";
            return r;
        }
        r.message = fmt::format("mean L |cos| / pdf {:.9g} estimates the {} {:.9g} (+- {:.3g}): difference {:.3g} = "
                                "{:.2f} standard errors ({} samples)", t.mean, what, t.reference, uncertainty,
                                t.mean - t.reference, t.t, e.moments.n);
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_light_irradiance_check() { return std::make_unique<LightIrradianceCheck>(); }

}  // namespace warpcheck::light
