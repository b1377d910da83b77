// "weight_mean" and "inverse_pdf_mean": importance-weighted estimators, tested
// against what they estimate. Both are statistical (a t-test of the mean, in the
// run's multiple-testing family) and both draw the random stream only (edge
// inputs are not distributed as the warp's samples).
//  - weight_mean: a weighted sampler's mean weight estimates the integral of
//    eval over the domain, since E[eval(X) / pdf(X)] = integral of eval. The
//    reference is eval integrated by the engine's adaptive quadrature. A pdf
//    that disagrees with what sample draws (a mixture whose lobe-selection
//    probability differs between sample and pdf) biases it.
//  - inverse_pdf_mean: for a sampler that returns its pdf and has no pdf
//    function, E[1 / pdf(X)] is the measure of the density's support. A case
//    whose support is smaller than its domain (empty buckets of a table, an
//    environment map's empty rows) declares it (WarpCaseInfo::support_measure)
//    and is tested against it, two-sided. Undeclared, the support is known
//    only to lie in the domain, so E[1/pdf] <= the domain's measure is tested
//    one-sided (a pdf too small somewhere fails; one too large passes unless
//    the support is declared), and the row says so. A returned pdf that is off
//    by a factor anywhere moves the mean.
// The t-test needs a finite variance of the estimator: E[w^2] = integral of
// eval^2 / pdf, and E[1/pdf^2] = integral of 1/pdf, finite when the pdf stays
// away from 0 where eval is not 0 (where it does not, the test is not valid).
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "chi2/binning.h"
#include "chi2/mean_test.h"
#include "chi2/quadrature.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/input_chunks.h"

namespace warpcheck {
namespace {

/// The rounding allowance of the reference, relative: the float eval / pdf (or
/// 1 / pdf) of every sample may be off by a few ulps in the same direction, so
/// the mean of 10^6 of them may be biased by up to ~16 ulps (2^-20) without any
/// error in the warp; it is added to the standard error in quadrature.
constexpr double kRoundingAllowance = 0x1p-20;

enum class Estimator { Weight, InversePdf };

struct ImportanceStats {
    chi2::Moments moments;
    uint64_t invalid = 0;  ///< samples whose estimate is NaN or infinite (or whose pdf is not positive)
    void merge(const ImportanceStats& o) {
        moments.merge(o.moments);
        invalid += o.invalid;
    }
};

ImportanceStats compute(const WarpCase& warp, const CheckContext& ctx, Estimator which) {
    auto parts = map_input_chunks<ImportanceStats>(ctx, warp.input_kind(), ctx.options().samples, false,
                                         [&](std::size_t, std::span<const WarpInput> inputs) {
        std::vector<WarpOutput> x(inputs.size());
        std::vector<double> value(inputs.size());
        warp.sample_with_value(inputs, x, value);
        ImportanceStats s;
        for (double v : value) {
            const double estimate = which == Estimator::Weight ? v : 1.0 / v;
            if (!std::isfinite(estimate) || (which == Estimator::InversePdf && !(v > 0.0))) ++s.invalid;
            else s.moments.add(estimate);
        }
        return s;
    });
    return merge_in_order(parts);
}

struct Reference {
    double value = 0.0;
    double error = 0.0;      ///< quadrature error estimate (0 for a measure)
    bool one_sided = false;  ///< an upper bound only: the support's measure is not declared
};

/// E[1/pdf]'s reference: the declared support's measure, or else the domain's as an upper bound.
Reference support_measure(const WarpCase& warp) {
    const double declared = warp.info().support_measure;
    if (declared > 0.0) return {declared, 0.0, false};
    return {warp.domain().measure(), 0.0, true};
}

/// The integral of eval over the domain, by the chi-square engine's quadrature.
Reference integral_of_eval(const WarpCase& warp, const CheckContext& ctx) {
    const chi2::Binning binning(warp.domain());
    const chi2::BatchPdf eval = [&](std::span<const chi2::DomainPoint> points, std::span<double> out) {
        std::vector<WarpOutput> x(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) x[i] = to_warp_output(points[i]);
        warp.eval(x, out);
    };
    chi2::QuadratureOptions options;
    options.sample_count = ctx.options().samples;
    const chi2::CellIntegrals integrals = chi2::integrate_cells(binning, eval, options, ctx.executor());
    return {integrals.total, integrals.error_total};
}

/// What the mean is compared with, in words.
std::string reference_text(Estimator which, const Reference& ref) {
    if (which == Estimator::Weight) return "the integral of eval";
    return ref.one_sided ? "at most the domain's measure (support not declared: one-sided)"
                         : "the declared support's measure";
}

void judge(CheckResult& r, const ImportanceStats& s, const chi2::MeanTest& t, Estimator which, const Reference& ref) {
    const char* what = which == Estimator::Weight ? "mean weight" : "mean 1/pdf";
    r.p_value = t.p_value;  // judged by the runner at the run's corrected level
    r.summary = fmt::format("{} {:.6g} vs {}{:.6g} (t = {:.2f}{})", what, t.mean, ref.one_sided ? "<= " : "",
                            t.reference, t.t, ref.one_sided ? ", one-sided: support not declared" : "");
    r.verdict = Verdict::Pass;
    if (s.invalid > 0) {
        r.verdict = Verdict::Fail;
        r.summary = fmt::format("{} of {} samples with a non-finite {}", s.invalid, s.invalid + s.moments.n,
                                which == Estimator::Weight ? "weight" : "1/pdf");
        r.message = r.summary + " (the estimator is then undefined)";
        return;
    }
    r.message = fmt::format("{} {:.9g} estimates {} {:.9g}: difference {:.3g} = {:.2f} standard errors "
                            "({} samples)", what, t.mean, reference_text(which, ref), t.reference,
                            t.mean - t.reference, t.t, s.moments.n);
}

/// The one-sided p-value of H0: E <= reference (large means reject), from the two-sided test's.
double upper_p_value(const chi2::MeanTest& t) {
    if (std::isnan(t.p_value)) return t.p_value;
    return t.t > 0.0 ? 0.5 * t.p_value : 1.0 - 0.5 * t.p_value;
}

class ImportanceCheck final : public Check {
public:
    explicit ImportanceCheck(Estimator which) : which_(which) {}
    std::string name() const override { return which_ == Estimator::Weight ? "weight_mean" : "inverse_pdf_mean"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"invalid_samples",
                             which_ == Estimator::Weight ? "samples with a non-finite weight" : "samples with a non-finite 1/pdf",
                             FigureRule::Zero}},
                .p_value = "p-value: the t-test's"};
    }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        if (name() == "weight_mean")
            return {name(), "The mean weight eval/pdf against the integral of eval (quadrature).",
                    "The t-test's two-sided p-value; where f's float noise reaches half its integral (no albedo "
                    "known), the one-sided p-value of the mean energy weight against 1."};
        return {name(), "The mean of 1/pdf against the domain's measure.",
                "The t-test's two-sided p-value."};
    }
    std::string description() const override {
        return which_ == Estimator::Weight
                   ? "the mean weight against the integral of eval over the domain (t-test, Sidak-corrected)"
                   : "without a pdf function: the mean of 1/pdf (returned) against the declared support's measure, "
                     "or one-sided against the domain's (t-test)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        if (warp.is_discrete()) return Applicability::not_about_such_cases();
        if (!std::isfinite(warp.domain().measure()) && !(warp.info().support_measure > 0.0))
            return Applicability::not_about_such_cases();
        if (which_ == Estimator::Weight)
            return Applicability::when(warp.sample_returns() == SampleReturns::PointAndWeight);
        return Applicability::when(warp.sample_returns() == SampleReturns::PointAndPdf && !warp.has_pdf());
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const ImportanceStats s = compute(warp, ctx, which_);
        const Reference ref = which_ == Estimator::Weight ? integral_of_eval(warp, ctx) : support_measure(warp);
        const double uncertainty = std::hypot(ref.error, kRoundingAllowance * std::abs(ref.value));
        chi2::MeanTest t = chi2::mean_test(s.moments, ref.value, uncertainty);
        if (ref.one_sided) t.p_value = upper_p_value(t);
        CheckResult r;
        r.samples = s.moments.n + s.invalid;
        r.figures = {{"samples", static_cast<double>(r.samples)},
                     {"mean", t.mean},
                     {"reference", ref.value},
                     {"reference_error", ref.error},
                     {"standard_error", t.standard_error},
                     {"t", t.t},
                     {"p_value", t.p_value},
                     {"invalid_samples", static_cast<double>(s.invalid)},
                     {"one_sided", ref.one_sided ? 1.0 : 0.0}};
        judge(r, s, t, which_, ref);
        return r;
    }

private:
    Estimator which_;
};

}  // namespace

std::unique_ptr<Check> make_weight_mean_check() { return std::make_unique<ImportanceCheck>(Estimator::Weight); }
std::unique_ptr<Check> make_inverse_pdf_mean_check() {
    return std::make_unique<ImportanceCheck>(Estimator::InversePdf);
}

}  // namespace warpcheck
