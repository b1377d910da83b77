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
#include "validate/checks/shared/cell_evidence.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/input_chunks.h"
#include "validate/checks/light/light_checks.h"
#include "validate/checks/light/light_integral.h"
#include "validate/checks/light/light_pilot.h"
#include "validate/checks/shared/power_level.h"

namespace warpcheck::light {
namespace {

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

SphereIntegral integrate(const LightCase& light, const CheckContext& ctx) {
    const chi2::Binning grid(light.domain(), kIntegralCells);
    const std::size_t pilot_count = chi2::kPilotPointsPerCell * grid.cell_count();
    std::vector<chi2::SamplePoint> pilot;
    double pilot_sum = 0.0;  // over the pilot's inputs: a declined sample adds 0
    for (const LightRecord& r : light_pilot(light, ctx, pilot_count)) {
        pilot.push_back(r.wi);
        pilot_sum += static_cast<double>(r.L) * light.cosine(r.wi) / r.pdf;
    }
    const DirectionIntegrand integrand = [&light](std::span<const WarpOutput> x, std::span<double> out, double scale) {
        light.radiance(x, out);
        for (std::size_t i = 0; i < x.size(); ++i) out[i] *= light.cosine(x[i]) / scale;
    };
    return integrate_sphere(pilot, pilot_sum / static_cast<double>(pilot_count), integrand, ctx);
}

class LightIrradianceCheck final : public Check {
public:
    std::string name() const override { return "light_irradiance"; }
    JudgedRules judged_rules() const override { return {.p_value = "p-value: the t-test's"}; }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "A light's irradiance estimator: the mean of L |cos| / pdf over its samples (0 where it "
                "declined) against the integral of its own L(ref, w) |cos| over the sphere (verified quadrature on "
                "cells placed by a pilot, with the light's float noise); non-finite estimates fail.",
                "The t-test's two-sided p-value, the integral's uncertainty added to the standard error."};
    }
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
        const SphereIntegral ref = integrate(light, ctx);
        return judge_estimate(light, e.moments, e.invalid, ref, ctx, light.on_surface() ? "irradiance" : "integral of L",
                              "L |cos| / pdf", "L cos / pdf: a pdf of 0 or NaN with light, or a non-finite L");
    }
};

}  // namespace

std::unique_ptr<Check> make_light_irradiance_check() { return std::make_unique<LightIrradianceCheck>(); }

}  // namespace warpcheck::light
