#include "validate/checks/light/light_integral.h"

#include <cmath>

#include <boost/math/distributions/normal.hpp>
#include <fmt/format.h>

#include "chi2/equal_probability.h"
#include "validate/checks/shared/cell_evidence.h"
#include "validate/checks/shared/power_level.h"

namespace warpcheck::light {

SphereIntegral integrate_sphere(const std::vector<chi2::SamplePoint>& pilot, double pilot_estimate,
                                const DirectionIntegrand& integrand, const CheckContext& ctx) {
    const chi2::Domain domain = chi2::Domain::sphere();
    const chi2::Binning grid(domain, kIntegralCells);
    const double scale = std::isfinite(pilot_estimate) && pilot_estimate > 0.0 ? pilot_estimate : 1.0;
    chi2::EqualProbabilityCells cells;
    if (!pilot.empty() &&
        chi2::effective_cells(grid, pilot) < chi2::kMinEffectiveCellShare * static_cast<double>(grid.cell_count()))
        cells = chi2::equal_probability_cells(grid, pilot, ctx.options().samples);
    const chi2::Binning binning = cells.edges.empty() ? grid : chi2::Binning(domain, grid.resolution(), cells.edges);
    const chi2::BatchPdf scaled = [&integrand, scale](std::span<const chi2::DomainPoint> points,
                                                      std::span<double> out) {
        std::vector<WarpOutput> x(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) x[i] = to_warp_output(points[i]);
        integrand(x, out, scale);
    };
    chi2::QuadratureOptions q;
    q.sample_count = ctx.options().samples;
    q.verify = true;
    q.float_noise = true;
    chi2::CellIntegrals c = chi2::integrate_cells(binning, scaled, q, ctx.executor());
    chi2::PilotRefinement refined = chi2::refine_by_pilot(binning, pilot, scaled, q, c, ctx.executor());
    refined.missed_mass *= scale;
    return {c.total * scale, c.error_total * scale, c.float_noise_total * scale, c.evaluations, refined};
}

double reference_uncertainty(const SphereIntegral& reference) {
    return std::hypot(reference.error, reference.float_noise, kRoundingAllowance * std::abs(reference.value));
}

double bias_for_power(const CheckContext& ctx, const chi2::MeanTest& t) {
    const boost::math::normal z;
    const double level = power_level(ctx.options(), 1);
    const double k = boost::math::quantile(boost::math::complement(z, 0.5 * level)) + boost::math::quantile(z, 0.9);
    return k * t.standard_error / std::abs(t.reference);
}

namespace {

/// The estimate's relative difference from the integral with its 99% interval
/// (2.576 standard errors of the t-test, the reference's uncertainty included;
/// the verdict's level is the run's, far smaller), as bsdf_albedo plots its
/// mean weight.
FamilyPoint estimate_point(const WarpCase& warp, const chi2::MeanTest& t, const char* what) {
    FamilyPoint p;
    p.family = warp.info().family;
    p.title = fmt::format("{}: estimate / integral - 1, against theta", what);
    p.x_label = "theta (degrees)";
    p.y_label = "estimate / integral - 1";
    std::vector<Parameter> others;
    for (const Parameter& q : warp.info().params)
        if (q.name == "theta") p.x = q.value;
        else others.push_back(q);
    const std::string name = case_name("", others);
    p.group = name.empty() ? name : name.substr(1, name.size() - 2);
    const double d = t.mean / t.reference - 1.0, half = 2.576 * t.standard_error / std::abs(t.reference);
    p.values = {{"estimate / integral - 1 (99% interval)", d, d - half, d + half}};
    p.limits = {{"agreement", 0.0}};
    return p;
}

}  // namespace

CheckResult judge_estimate(const WarpCase& warp, const chi2::Moments& moments, uint64_t invalid,
                           const SphereIntegral& reference, const CheckContext& ctx, const char* what,
                           const char* estimator, const char* invalid_why, std::vector<Figure> extra) {
    const chi2::MeanTest t = chi2::mean_test(moments, reference.value, reference_uncertainty(reference));
    CheckResult r;
    r.samples = moments.n + invalid;
    r.figures = {{"samples", static_cast<double>(r.samples)},
                 {"mean", t.mean},
                 {"reference", reference.value},
                 {"reference_error", reference.error},
                 {"reference_float_noise", reference.float_noise},
                 {"standard_error", t.standard_error},
                 {"t", t.t},
                 {"p_value", t.p_value},
                 {"invalid_samples", static_cast<double>(invalid)},
                 {"evaluations", static_cast<double>(reference.evaluations)}};
    for (Figure& f : extra) r.figures.push_back(std::move(f));
    add_pilot_refinement_figures(r.figures, reference.refinement);
    const double power_bias = bias_for_power(ctx, t);
    r.figures.push_back({"power_relative_bias", power_bias});
    r.p_value = t.p_value;
    r.verdict = Verdict::Pass;
    if (std::isfinite(t.mean) && t.reference != 0.0) r.family_points.push_back(estimate_point(warp, t, what));
    r.summary = fmt::format("{} {:.6g} vs {:.6g} (t = {:.2f}); 90% power: bias {:.2g}%", what, t.mean, t.reference,
                            t.t, 100.0 * power_bias);
    if (!(power_bias <= kStatedBias))
        r.weak = fmt::format("cannot see a {:.0f}% bias of the {} (90% power only at {:.2g}%): {}",
                             100.0 * kStatedBias, what, 100.0 * power_bias,
                             reference_uncertainty(reference) > t.standard_error / std::sqrt(2.0)
                                 ? "the integral's own bound is most of the uncertainty"
                                 : "more samples would");
    if (invalid > 0) {
        r.verdict = Verdict::Fail;
        r.summary = fmt::format("{} of {} estimates not finite", invalid, r.samples);
        r.message = r.summary + " (" + invalid_why + ")";
        return r;
    }
    r.message = fmt::format("mean {} {:.9g} estimates the {} {:.9g} (+- {:.3g}): difference {:.3g} = {:.2f} "
                            "standard errors ({} samples)", estimator, t.mean, what, t.reference,
                            reference_uncertainty(reference), t.mean - t.reference, t.t, moments.n);
    return r;
}

}  // namespace warpcheck::light
