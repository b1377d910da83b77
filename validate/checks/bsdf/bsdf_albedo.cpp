// "bsdf_albedo": the mean weight against the directional albedo, and the
// albedo against 1 (energy conservation).
//
// The mean of the weights f |cos theta_i| / pdf over all draws (a draw without
// a sample weighs 0) estimates the directional albedo: the integral of
// f(wo, .) |cos theta_i| over the sphere (by the chi-square engine's
// quadrature) plus, for each delta lobe, its claimed probability times its
// samples' mean weight. Rules:
//  - statistical: Student's t-test of the mean weight against that albedo,
//    the quadrature's error bound and a 2^-20 relative rounding allowance
//    (the float weights of 10^6 samples rounding the same way) added to the
//    standard error, and the albedo known within twice the float noise of f
//    (chi2::kFloatNoiseFactor, the allowance chi2 and bsdf_chi2 grant a float
//    pdf; --strict withholds it) as a band; in the run's Sidak family;
//  - the energy albedo, the same integral with transmitted directions' f
//    times (eta(wi) / eta(wo))^2 in radiance transport (undoing radiance's
//    1 / etap^2, BsdfCase::energy_factor), may exceed 1 by at most the
//    quadrature's error bound plus 2^-20 (the density's float rounding, as
//    chi2::kIntegralTolerance) plus the same float-noise allowance as the
//    albedo's, times the largest energy factor (the energy integral's noise
//    is the albedo's, weighted by it): more is energy created by the surface
//    (FAIL).
//    One-sided: an albedo below 1 is a surface that absorbs.
//  - where that float-noise allowance reaches half the integral of f |cos|
//    (kUnknownAlbedoShare: a lobe narrower than the float directions that
//    evaluate it), the quadrature knows no albedo: the two rules above are not
//    made, and energy is judged from the samples alone, a one-sided t-test of
//    the mean energy weight against 1 (the row's p-value, in the Sidak family
//    as the first test's; a sampler whose weights are not f |cos| / pdf is
//    bsdf_weight's to find).
// Evidence: the albedo and energy albedo against theta_o at this case's
// azimuth (a cheaper quadrature per angle, kSweepAccuracySamples), and the
// case's points on its family's plots across its grid (the mean weight with
// its 99% interval, the albedo, the energy albedo and its bound 1; the mean
// weight minus the albedo with that interval).
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "chi2/chi2_test.h"
#include "chi2/equal_probability.h"
#include "chi2/mean_test.h"
#include "validate/checks/bsdf/bsdf_checks.h"
#include "validate/checks/bsdf/bsdf_common.h"
#include "validate/checks/bsdf/bsdf_statistics.h"
#include "validate/checks/shared/cell_evidence.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/power_level.h"

namespace warpcheck::bsdf {
namespace {

/// Relative rounding allowance of the reference and of the energy bound: 2^-20 (16 float ulps).
constexpr double kRoundingAllowance = 0x1p-20;
/// The albedo quadrature's cells: 16 azimuths by 32 heights, whose rows split
/// the sphere at z = 0, so each cell lies on one side of the surface.
constexpr chi2::BinResolution kAlbedoCells{16, 32};
/// The sweep's quadrature: 4 azimuths by 8 heights, and the accuracy rule of
/// 10^4 samples (an error bound of about 1e-3 of the albedo, far below the
/// curve's features, and reported).
constexpr chi2::BinResolution kSweepCells{4, 8};
constexpr uint64_t kSweepAccuracySamples = 10'000;
/// Where f's float-noise allowance is at least this share of the integral of
/// f |cos|, the integral is known only within a factor of 3 (I/2 to 3I/2),
/// which is no albedo to hold weights or energy to, and it is more float
/// rounding than f: the first-order noise estimate (the change over one float
/// step of wi) no longer even bounds it. Henyey-Greenstein, albedo 1: at
/// g = 0.99999 the integral is 273 with an allowance of 232, at 0.9999 3.06
/// with 2.28; at 0.999 it is 0.988 with 0.24 (24%), at 0.99 1 - 1e-4 with 0.005.
constexpr double kUnknownAlbedoShare = 0.5;

struct Draws {
    chi2::Moments weights, energy;
    DeltaTally delta;
    void merge(const Draws& o) {
        weights.merge(o.weights);
        energy.merge(o.energy);
        delta.merge(o.delta);
    }
};

Draws draw(const BsdfCase& bsdf, const CheckContext& ctx) {
    const auto parts = map_bsdf_chunks<Draws>(ctx, bsdf, ctx.options().samples, false,
                                              [&](std::size_t, std::span<const WarpInput>, std::span<const BsdfRecord> rec) {
        Draws d;
        for (const BsdfRecord& r : rec) {
            const double w = r.sampled() ? static_cast<double>(r.f) * bsdf.cosine(r.wi) / r.pdf : 0.0;
            d.weights.add(w);
            d.energy.add(r.sampled() ? w * bsdf.energy_factor(r.wi) : 0.0);
            if (r.sampled() && r.delta()) d.delta.add(bsdf, r);
        }
        return d;
    });
    return merge_in_order(parts);
}

/// The integral of f(wo, .) |cos theta_i| over the sphere, plain and as
/// energy (wo on the case's side of the surface, so energy_factor applies).
struct Albedo {
    double albedo = 0.0, energy = 0.0, error = 0.0;
    double float_noise = 0.0;  ///< the integral of f |cos|'s change over one float step of wi
    uint64_t evaluations = 0;
    chi2::PilotRefinement pilot_refinement;
};

/// With a pilot of the sampler's continuous samples, the cells where it
/// clusters are integrated again on pieces it places (chi2::refine_by_pilot):
/// a lobe thinner than the cells' nodes (an anisotropic conductor of alpha
/// 1e-3 x 1 seen from grazing: a sheet whose mass the nodes stepped over,
/// 0.2% of the albedo, t = 13 against a correct sampler) is integrated where
/// the samples show it is.
Albedo integrate(const BsdfCase& bsdf, Vector3f wo, chi2::BinResolution cells, uint64_t accuracy_samples,
                 const chi2::ParallelFor& parallel, bool float_noise = false,
                 std::span<const std::array<float, 3>> pilot = {}) {
    const chi2::Binning binning(bsdf.domain(), cells);
    chi2::QuadratureOptions q;
    q.sample_count = accuracy_samples;
    q.float_noise = float_noise;
    chi2::CellIntegrals c = chi2::integrate_cells(binning, albedo_integrand(bsdf, wo), q, parallel);
    chi2::PilotRefinement refined;
    if (!pilot.empty()) refined = chi2::refine_by_pilot(binning, pilot, albedo_integrand(bsdf, wo), q, c, parallel);
    Albedo a{0.0, 0.0, c.error_total, c.float_noise_total, c.evaluations, refined};
    for (std::size_t i = 0; i < c.probability.size(); ++i) {
        const chi2::ParamRect r = binning.cell_rect(i);
        // The factor is constant on each side of the surface, and no cell straddles it.
        const WarpOutput middle{0.0f, 0.0f, static_cast<float>(0.5 * (r.v0 + r.v1))};
        a.albedo += c.probability[i];
        a.energy += c.probability[i] * bsdf.energy_factor(middle);
    }
    return a;
}

/// The delta lobes' part of the albedo: claimed probability times mean weight.
double delta_albedo(const DeltaTally& d, bool energy) {
    double sum = 0.0;
    for (const DeltaTally::Lobe& l : d.lobes) sum += l.claimed() * (energy ? l.mean_energy() : l.mean_weight());
    return sum;
}

double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

/// The (energy) albedo of the continuous lobes against theta_o on wo's side,
/// at wo's azimuth: the same f at other wo. Returns the curves' largest
/// quadrature error bound in `worst_error`.
Plot albedo_sweep(const BsdfCase& bsdf, double own_albedo, double mean_weight, double& worst_error) {
    const Vector3f wo = bsdf.wo();
    const double phi = degrees(std::atan2(static_cast<double>(wo.y), static_cast<double>(wo.x)));
    const bool below = wo.z < 0.0f;
    const double own = degrees(std::acos(std::abs(static_cast<double>(wo.z))));
    Series albedo{"albedo, continuous lobes", {}, {}}, energy{"energy albedo, continuous lobes", {}, {}};
    for (double theta = 0.0; theta <= 89.0; theta += theta < 85.0 ? 5.0 : 4.0) {
        const Vector3f w = bsdf_direction(below ? 180.0 - theta : theta, phi);
        const Albedo a = integrate(bsdf, w, kSweepCells, kSweepAccuracySamples, chi2::serial_for);
        worst_error = std::max(worst_error, a.error);
        albedo.x.push_back(theta);
        albedo.y.push_back(a.albedo);
        energy.x.push_back(theta);
        energy.y.push_back(a.energy);
    }
    Plot plot;
    plot.kind = Plot::Kind::Lines;
    plot.title = "albedo against theta_o of " + bsdf.name() + " (at its phi_o)";
    plot.x_label = below ? "theta_o from below the surface (degrees)" : "theta_o (degrees)";
    plot.y_label = "albedo";
    plot.series = {std::move(albedo), std::move(energy), {"energy bound", {0.0, 90.0}, {1.0, 1.0}},
                   {"this case: albedo", {own}, {own_albedo}}, {"this case: mean weight", {own}, {mean_weight}}};
    return plot;
}

struct Outcome {
    Albedo integral;
    double albedo = 0.0, energy = 0.0, energy_tolerance = 0.0;
    /// The float-rounding allowance of the reference: kFloatNoiseFactor times
    /// the integral of f |cos|'s float noise (0 under --strict), as chi2's and
    /// bsdf_chi2's normalisation rules grant the pdf's.
    double float_allowance = 0.0;
    /// False where the allowance reaches kUnknownAlbedoShare of the integral:
    /// `test` is then the one-sided test of the mean energy weight against 1.
    bool albedo_known = true;
    chi2::MeanTest test;
};

/// One-sided t-test of H0: mean energy weight <= 1 (a surface that absorbs is
/// correct): the two-sided test's p halved above 1, 1 at or below it. The
/// mean's rounding (2^-20 of it) is the reference's uncertainty, as above.
chi2::MeanTest energy_weight_test(const chi2::Moments& energy) {
    chi2::MeanTest t = chi2::mean_test(energy, 1.0, kRoundingAllowance);
    if (!std::isnan(t.p_value)) t.p_value = t.mean > 1.0 ? 0.5 * t.p_value : 1.0;
    return t;
}

Outcome evaluate(const BsdfCase& bsdf, const CheckContext& ctx, const Draws& d) {
    Outcome o;
    const std::vector<std::array<float, 3>> pilot =
        continuous_pilot(bsdf, ctx, chi2::kPilotPointsPerCell * chi2::Binning(bsdf.domain(), kAlbedoCells).cell_count());
    o.integral = integrate(bsdf, bsdf.wo(), kAlbedoCells, ctx.options().samples, ctx.executor(), true, pilot);
    o.albedo = o.integral.albedo + delta_albedo(d.delta, false);
    o.energy = o.integral.energy + delta_albedo(d.delta, true);
    o.energy_tolerance = o.integral.error + kRoundingAllowance;
    // A float f of a sharp lobe (Henyey-Greenstein's textbook form at g =
    // 0.99) integrates to 1e-4 less than its sampler's weights of exactly 1
    // say: the same rounding that chi2 allows the pdf, granted here as a band
    // (a bound every weight shares, not noise that averages out).
    o.float_allowance = ctx.options().strict ? 0.0 : chi2::kFloatNoiseFactor * o.integral.float_noise;
    o.test = chi2::mean_test(d.weights, o.albedo, std::hypot(o.integral.error, kRoundingAllowance * o.albedo),
                             o.float_allowance);
    // energy_factor depends only on wi's side of the surface.
    const double largest_factor = std::max(bsdf.energy_factor({0.0f, 0.0f, 1.0f}), bsdf.energy_factor({0.0f, 0.0f, -1.0f}));
    o.energy_tolerance += o.float_allowance * std::max(1.0, largest_factor);
    if (o.float_allowance > 0.0 && o.float_allowance >= kUnknownAlbedoShare * o.integral.albedo) {
        o.albedo_known = false;
        o.test = energy_weight_test(d.energy);
    }
    return o;
}

/// The verdict where the quadrature knows no albedo (Outcome::albedo_known).
void judge_by_weights(CheckResult& r, const Outcome& o) {
    r.p_value = o.test.p_value;  // judged by the runner at the run's corrected level
    r.verdict = Verdict::Pass;
    r.summary = fmt::format("mean energy weight {:.6g} vs 1 (one-sided t = {:.2f}); albedo unknown to the quadrature "
                            "(f's float noise {:.3g} of its integral {:.3g})",
                            o.test.mean, o.test.t, o.float_allowance, o.integral.albedo);
    r.message = fmt::format("the lobe is narrower than the float directions that evaluate f: its integral {:.9g} "
                            "carries a float-noise allowance of {:.3g}, at least {} of itself, so no albedo is known "
                            "to hold the mean weight or the energy to; energy is judged from the samples: mean energy "
                            "weight {:.9g}, {:.2f} standard errors above 1 (one-sided)",
                            o.integral.albedo, o.float_allowance, kUnknownAlbedoShare, o.test.mean, o.test.t);
}

void judge(CheckResult& r, const Outcome& o) {
    if (!o.albedo_known) return judge_by_weights(r, o);
    r.p_value = o.test.p_value;  // judged by the runner at the run's corrected level
    r.summary = fmt::format("mean weight {:.6g} vs albedo {:.6g} (t = {:.2f}); energy {:.6g}", o.test.mean, o.albedo,
                            o.test.t, o.energy);
    r.message = fmt::format("mean weight {:.9g} estimates the albedo {:.9g} (integral of f |cos| {:.9g} plus delta "
                            "lobes {:.9g}): {:.2f} standard errors; energy albedo {:.9g} (bound 1 + {:.3g})",
                            o.test.mean, o.albedo, o.integral.albedo, o.albedo - o.integral.albedo, o.test.t, o.energy,
                            o.energy_tolerance);
    r.verdict = Verdict::Pass;
    if (!(o.energy <= 1.0 + o.energy_tolerance)) {
        r.verdict = Verdict::Fail;
        r.summary = fmt::format("energy albedo {:.6g} exceeds 1 (tolerance {:.3g})", o.energy, o.energy_tolerance);
        r.message = "the surface creates energy: " + r.message;
    }
}

/// The case's points on its family's plots across its grid: the mean weight
/// with its 99% interval (2.576 standard errors of the t-test, the reference's
/// uncertainty included; the verdict's level is the run's, far smaller), the
/// albedo it estimates, the energy albedo where it differs (transmission in
/// radiance transport) and its bound 1; and their difference, whose interval
/// is too narrow to see beside an albedo near 1, against 0.
std::vector<FamilyPoint> albedo_points(const BsdfCase& bsdf, const Outcome& o) {
    const double half = 2.576 * o.test.standard_error;
    FamilyPoint albedo = family_point(bsdf, "albedo against theta_o", "albedo");
    if (!o.albedo_known) {  // no albedo to plot or to subtract: the energy weights against their bound
        albedo.values = {{"mean energy weight (99% interval)", o.test.mean, o.test.mean - half, o.test.mean + half}};
        albedo.limits = {{"energy bound", 1.0}};
        return {std::move(albedo)};
    }
    albedo.values = {{"mean weight (99% interval)", o.test.mean, o.test.mean - half, o.test.mean + half},
                     {"albedo", o.albedo}};
    if (o.energy != o.albedo) albedo.values.push_back({"energy albedo", o.energy});
    albedo.limits = {{"energy bound", 1.0}};
    FamilyPoint difference = family_point(bsdf, "mean weight minus albedo against theta_o", "mean weight - albedo");
    const double d = o.test.mean - o.albedo;
    difference.values = {{"mean weight - albedo (99% interval)", d, d - half, d + half}};
    difference.limits = {{"agreement", 0.0}};
    return {std::move(albedo), std::move(difference)};
}

/// The energy albedo against 1, where the albedo is known.
void energy_bound_line(const CheckResult& r, std::vector<JudgedQuantity>& out) {
    const auto energy = r.figure("energy_albedo"), bound = r.figure("energy_tolerance");
    if (!energy || !bound || r.figure("albedo_known").value_or(1.0) == 0.0) return;
    out.push_back(with_margin({"energy albedo", fmt::format("{:.9g}", *energy), "\u2264 1 + " + judged_number(*bound),
                               *energy <= 1.0 + *bound ? JudgedQuantity::State::Within : JudgedQuantity::State::Beyond},
                              std::max(0.0, *energy - 1.0), *bound));
}

class BsdfAlbedoCheck final : public BsdfCheck {
public:
    std::string name() const override { return "bsdf_albedo"; }
    JudgedRules judged_rules() const override {
        return {.p_value = "p-value: the t-test's", .bounds = energy_bound_line};
    }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "The mean weight against the directional albedo (the integral of f |cos| plus the delta "
                "lobes), and the energy albedo against 1 (energy created fails).",
                "The t-test's two-sided p-value; where f's float noise reaches half its integral (no albedo known), "
                "the one-sided p-value of the mean energy weight against 1."};
    }
    std::string description() const override {
        return "BSDF: the mean weight against the directional albedo (t-test, Sidak-corrected), and the energy "
               "albedo at most 1";
    }

protected:
    Applicability bsdf_applicability(const BsdfCase& b) const override {
        return unless_stochastic(b, "the values of f that a quadrature of the albedo would integrate");
    }

    CheckResult run_bsdf(const BsdfCase& bsdf, const CheckContext& ctx) const override {
        const Draws d = draw(bsdf, ctx);
        const Outcome o = evaluate(bsdf, ctx, d);
        CheckResult r;
        r.samples = d.weights.n;
        const double level = power_level(ctx.options(), 1);
        const double detectable = detectable_shift_in_standard_errors(level) * o.test.standard_error;
        r.figures = {{"samples", static_cast<double>(d.weights.n)},
                     {"mean_weight", o.test.mean},
                     {"albedo", o.albedo},
                     {"albedo_continuous", o.integral.albedo},
                     {"quadrature_error", o.integral.error},
                     {"quadrature_evaluations", static_cast<double>(o.integral.evaluations)},
                     {"standard_error", o.test.standard_error},
                     {"t", o.test.t},
                     {"p_value", o.test.p_value},
                     {"energy_albedo", o.energy},
                     {"energy_mean_weight", d.energy.mean},
                     {"energy_tolerance", o.energy_tolerance},
                     {"float_noise_allowance", o.float_allowance},
                     {"albedo_known", o.albedo_known ? 1.0 : 0.0},
                     {"power_weight_error", detectable},
                     {"power_relative_weight_error", detectable / o.albedo},
                     {"power_level", level}};
        add_pilot_refinement_figures(r.figures, o.integral.pilot_refinement);
        judge(r, o);
        r.family_points = albedo_points(bsdf, o);
        if (!bsdf.phase_function()) {
            double sweep_error = 0.0;
            r.plots.push_back(albedo_sweep(bsdf, o.integral.albedo, o.test.mean, sweep_error));
            r.figures.push_back({"sweep_quadrature_error", sweep_error});
        }
        return r;
    }
};

/// "bsdf_energy": energy from the samples alone, bsdf_albedo's fallback rule
/// run on its own, no quadrature: cheap at any parameter (a lobe of roughness
/// 1e-4 or g = 0.99999 costs what a diffuse one does), so --fuzz runs it at
/// the ends of the families' ranges. Not a default check: bsdf_albedo already
/// holds the energy to 1 and the weights to the albedo by quadrature.
class BsdfEnergyCheck final : public BsdfCheck {
public:
    std::string name() const override { return "bsdf_energy"; }
    bool statistical() const override { return true; }
    bool runs_by_default(const RunOptions&) const override { return false; }
    CheckLegend legend() const override {
        return {name(), "The mean energy weight of the samples against 1, without quadrature (run by --fuzz).",
                "The one-sided t-test's p-value of the mean energy weight above 1."};
    }
    std::string description() const override {
        return "BSDF: the mean energy weight of the samples at most 1 (one-sided t-test, Sidak-corrected); no "
               "quadrature, for --fuzz";
    }

protected:
    Applicability bsdf_applicability(const BsdfCase&) const override { return Applicability::runs(); }

    CheckResult run_bsdf(const BsdfCase& bsdf, const CheckContext& ctx) const override {
        const Draws d = draw(bsdf, ctx);
        const chi2::MeanTest t = energy_weight_test(d.energy);
        CheckResult r;
        r.samples = d.energy.n;
        r.figures = {{"samples", static_cast<double>(d.energy.n)},
                     {"energy_mean_weight", t.mean},
                     {"standard_error", t.standard_error},
                     {"t", t.t},
                     {"p_value", t.p_value}};
        r.p_value = t.p_value;  // judged by the runner at the run's corrected level
        r.verdict = Verdict::Pass;
        r.summary = fmt::format("mean energy weight {:.6g} vs 1 (one-sided t = {:.2f})", t.mean, t.t);
        r.message = fmt::format("mean energy weight {:.9g} over {} draws (a draw without a sample weighs 0): {:.2f} "
                                "standard errors above 1 (one-sided; 1 + 2^-20 is the bound's rounding)",
                                t.mean, d.energy.n, t.t);
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_bsdf_albedo_check() { return std::make_unique<BsdfAlbedoCheck>(); }
std::unique_ptr<Check> make_bsdf_energy_check() { return std::make_unique<BsdfEnergyCheck>(); }

}  // namespace warpcheck::bsdf
