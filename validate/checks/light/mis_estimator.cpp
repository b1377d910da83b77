// "mis_estimator": the multi-sample MIS estimator a renderer's direct
// lighting forms, one sample of every strategy per input, each weighted by
// the heuristic of the pdf its sampler returned beside the other strategies'
// pdfs as the MIS sum evaluates them and divided by the returned pdf, has the
// integral of f(wo, wi) L(ref, wi) |cos theta_i| over the sphere as its mean.
// Any weights that sum to 1 keep it unbiased; weights that do not (a pdf in
// another measure in the sum, a missing selection probability), a pdf off
// from its sampler's density, or a value that is not the integrand's bias it.
// Statistical: a t-test of the mean in the run's multiple-testing family, on
// the reference light_irradiance uses (light_integral.h), with cells placed
// by a pilot of the strategies' samples that carry light, so that both the
// light and the lobe where it meets the light get cells of their own.
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "chi2/binning.h"
#include "chi2/equal_probability.h"
#include "chi2/mean_test.h"
#include "validate/api/light_case.h"
#include "validate/checks/shared/cell_evidence.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/input_chunks.h"
#include "validate/checks/light/light_checks.h"
#include "validate/checks/light/light_integral.h"

namespace warpcheck::light {
// A named namespace around the file's own names: the unity build compiles
// this file with the other light checks, whose anonymous namespaces hold
// names of their own (Example, compute, Estimates, integrate).
namespace mis_estimator_check {
namespace {

struct Estimates {
    chi2::Moments moments;
    uint64_t invalid = 0;
    std::vector<double> part_sums;  // each strategy's weighted contributions, summed
    void merge(const Estimates& o) {
        moments.merge(o.moments);
        invalid += o.invalid;
        part_sums.resize(std::max(part_sums.size(), o.part_sums.size()), 0.0);
        for (std::size_t s = 0; s < o.part_sums.size(); ++s) part_sums[s] += o.part_sums[s];
    }
};

/// The estimates of one batch of inputs: every strategy samples each input;
/// a sample's weight uses its returned pdf beside the others' MIS pdfs.
/// Each input's estimate is added to `out`, or counted invalid.
Estimates estimate_batch(const MisCase& mis, std::span<const WarpInput> inputs, std::vector<double>* points = nullptr,
                         std::vector<chi2::SamplePoint>* directions = nullptr) {
    const std::size_t n = inputs.size(), k = mis.strategy_count();
    std::vector<double> total(n, 0.0), part(n), others(k - 1);
    std::vector<std::vector<double>> mis_pdf(k, std::vector<double>(n));
    std::vector<MisRecord> rec(n);
    std::vector<WarpOutput> wi(n);
    Estimates e;
    e.part_sums.assign(k, 0.0);
    for (std::size_t s = 0; s < k; ++s) {
        mis.sample_strategy(s, inputs, rec);
        for (std::size_t i = 0; i < n; ++i) wi[i] = rec[i].wi;
        for (std::size_t t = 0; t < k; ++t)
            if (t != s) mis.mis_pdf(t, wi, mis_pdf[t]);
        for (std::size_t i = 0; i < n; ++i) {
            if (!rec[i].sampled()) continue;  // no sample: it adds 0
            // The pilot places the reference's cells where the integrand is
            // (on the lights, and where the lobe meets them), not where a
            // strategy draws samples that carry nothing.
            if (directions != nullptr && rec[i].value != 0.0) directions->push_back(rec[i].wi);
            for (std::size_t t = 0, m = 0; t < k; ++t)
                if (t != s) others[m++] = mis_pdf[t][i];
            const double pdf = static_cast<double>(rec[i].pdf);
            const double v = rec[i].value == 0.0 ? 0.0 : mis.weight(pdf, others) * rec[i].value / pdf;
            total[i] += v;
            if (std::isfinite(v)) e.part_sums[s] += v;
        }
    }
    for (double v : total) {
        if (!std::isfinite(v)) ++e.invalid;
        else e.moments.add(v);
        if (points != nullptr) points->push_back(v);
    }
    return e;
}

Estimates estimate(const MisCase& mis, const CheckContext& ctx) {
    auto parts = map_input_chunks<Estimates>(ctx, InputKind::Uniform3D, ctx.options().samples, false,
                                             [&](std::size_t, std::span<const WarpInput> inputs) {
        return estimate_batch(mis, inputs);
    });
    return merge_in_order(parts);
}

SphereIntegral integrate(const MisCase& mis, const CheckContext& ctx) {
    const chi2::Binning grid(mis.domain(), kIntegralCells);
    const std::vector<WarpInput> in = pilot_inputs(ctx, InputKind::Uniform3D, chi2::kPilotPointsPerCell *
                                                                                  grid.cell_count() /
                                                                                  mis.strategy_count());
    std::vector<double> values;
    std::vector<chi2::SamplePoint> pilot;
    estimate_batch(mis, in, &values, &pilot);
    std::erase_if(pilot, [](const chi2::SamplePoint& p) { return !std::isfinite(p[0] + p[1] + p[2]); });
    double sum = 0.0;
    for (double v : values)
        if (std::isfinite(v)) sum += v;
    const DirectionIntegrand integrand = [&mis](std::span<const WarpOutput> x, std::span<double> out, double scale) {
        mis.integrand(x, out);
        for (double& v : out) v /= scale;
    };
    return integrate_sphere(pilot, values.empty() ? 1.0 : sum / static_cast<double>(values.size()), integrand, ctx);
}

class MisEstimatorCheck final : public Check {
public:
    std::string name() const override { return "mis_estimator"; }
    JudgedRules judged_rules() const override { return {.p_value = "p-value: the t-test's"}; }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "The multi-sample MIS estimator, one sample of every strategy per input, weighted by the "
                "heuristic and divided by the returned pdf, against the integral of f L |cos| over the sphere "
                "(verified quadrature on cells placed by a pilot of the strategies' lit samples).",
                "The t-test's two-sided p-value, the integral's uncertainty added to the standard error."};
    }
    std::string description() const override {
        return "MIS: the mean of the weighted sum over strategies of f L |cos| / pdf against the integral of "
               "f L |cos| over the sphere (t-test, Sidak-corrected)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        return Applicability::when(as_mis(warp) != nullptr);
    }
    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const MisCase& mis = *as_mis(warp);
        const Estimates e = estimate(mis, ctx);
        const SphereIntegral ref = integrate(mis, ctx);
        std::vector<Figure> parts;
        std::string named;
        const double n = static_cast<double>(std::max<uint64_t>(e.moments.n + e.invalid, 1));
        for (std::size_t s = 0; s < e.part_sums.size(); ++s) {
            parts.push_back({s == 0 ? std::string("bsdf_part") : fmt::format("light_part_{}", s), e.part_sums[s] / n});
            named += fmt::format("{}{} {:.6g}", s == 0 ? "" : ", ", mis.strategy_name(s), e.part_sums[s] / n);
        }
        CheckResult r = judge_estimate(mis, e.moments, e.invalid, ref, ctx, "integral of f L |cos|", "MIS estimate",
                                       "weight f L cos / pdf: a pdf of 0 or NaN with light, or a non-finite value",
                                       std::move(parts));
        r.message += "; each strategy's weighted part: " + named;
        return r;
    }
};

}  // namespace
}  // namespace mis_estimator_check

std::unique_ptr<Check> make_mis_estimator_check() { return std::make_unique<mis_estimator_check::MisEstimatorCheck>(); }

}  // namespace warpcheck::light
