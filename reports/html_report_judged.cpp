// The legend of each check's p-value, a row's closeness to its limit, and the
// judged tests of an unbinned row that its plots mark. The judged quantities
// themselves are the checks' own (CheckResult::judged, validate/checks/judged.h).
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "reports/html_report_parts.h"
#include "reports/terminal_table.h"
#include "reports/text.h"

namespace warpcheck::html {
namespace {

/// What each check judges and how its p-value is formed, for the legend.
const std::vector<std::pair<std::string_view, CheckLegend>> kLegends = {
    {"chi2",
     {"Pearson's X\u00b2 of the samples over cells against the pdf integrated over each cell (cells expected "
      "below 5 pooled), and the single cell least likely under the model; also fails on samples outside the "
      "domain, NaN samples, samples where the density is 0, and an integral off 1 beyond its tolerance.",
      "min(p_X\u00b2 / 0.8, p_cell / 0.2), weighted Bonferroni: Pearson gets 80% of the level, the largest "
      "residual (its exact binomial p, \u0160id\u00e1k over the cells) 20%. The summary's p is Pearson's alone."}},
    {"unbinned",
     {"The empirical CDF of each marginal against the CDF of the pdf: Anderson\u2013Darling on every marginal, and "
      "Kuiper too on an azimuth (KS is shown, not judged); where float resolution and the CDF's error could shift the "
      "CDF, each sample is tested within its band (conservative p); a marginal whose CDF is not accurate enough is "
      "left untested.",
      "1 \u2212 (1 \u2212 min p)^k, \u0160id\u00e1k over the k judged tests. The summary's \u201cmin p\u201d is "
      "before the correction."}},
    {"binade", {"Pearson's X\u00b2 of the mass per binade and of the significand parity within binades, and where "
                "the interval allows, of each binary digit of (x \u2212 a) / (b \u2212 a).",
                "min(1, k \u00d7 min p) over the k tests made (Bonferroni)."}},
    {"discrete_chi2", {"Pearson's X\u00b2 of the category counts against the pmf; a category of pmf 0 chosen fails.",
                       "Pearson's p-value."}},
    {"remapped_u", {"The remapped u: overall KS against uniform, and a X\u00b2 of u within each category.",
                    "min(p_KS / 0.5, p_X\u00b2 / 0.5) (weighted Bonferroni)."}},
    {"weight_mean", {"The mean weight eval/pdf against the integral of eval (quadrature).",
                     "The t-test's two-sided p-value; where f's float noise reaches half its integral (no albedo "
                     "known), the one-sided p-value of the mean energy weight against 1."}},
    {"inverse_pdf_mean", {"The mean of 1/pdf against the domain's measure.", "The t-test's two-sided p-value."}},
    {"roundtrip", {"|invert(sample(u)) \u2212 u| against the case's tolerance (float resolution); excused "
                   "classes (resolution-limited, degenerate, other preimage, rounded to 1) are counted and bounded.",
                   ""}},
    {"exhaustive_roundtrip", {"Every float u of [0, 1): the round trip, a monotone sample(u), a finite positive pdf.", ""}},
    {"exhaustive", {"Every input: outputs outside [a, b), steps down of a monotone sampler and a reach leaving more "
                    "mass out than one input's (monotone) or than independent draws leave at 1e-9 (hash) fail; the "
                    "bias of single floats is reported.", ""}},
    {"tabulated", {"sample(u) and pdf against the inversion method on a 65536-bucket table of the density: each "
                   "error over its tolerance.", ""}},
    {"consistency", {"Every sample lies in the domain and has a finite, positive pdf: counts must be 0, but for a pdf "
                     "of 0 on the boundary, and one beside a positive pdf (float rounding at a support's edge) within "
                     "its Poisson bound.", ""}},
    {"sample_pdf", {"The pdf that sample returns against pdf(x), within float rounding.", ""}},
    {"weight", {"The weight that sample returns against eval(x) / pdf(x), within float rounding.", ""}},
    {"pmf", {"The pmf is finite, non-negative and sums to 1 within float rounding.", ""}},
    {"bsdf_chi2",
     {"The continuous lobes' wi over cells of the sphere against pdf(wo, .) (Pearson's X\u00b2 and the largest "
      "residual, with the chi2 check's float-aware cells and bands), and the share of draws that landed against "
      "pdf(wo, .)'s integral; also fails on samples where the pdf integrates to 0 and an integral above what the "
      "continuous lobes hold.",
      "min(p_X\u00b2 / 0.7, p_cell / 0.2, p_landing / 0.1), weighted Bonferroni."}},
    {"bsdf_unbinned",
     {"The continuous lobes' phi_i and cos theta_i against their CDFs from pdf(wo, .): the unbinned check's "
      "Anderson\u2013Darling on both and Kuiper on the azimuth, each sample within its float band where that matters.",
      "1 \u2212 (1 \u2212 min p)^k, \u0160id\u00e1k over the k judged tests."}},
    {"bsdf_weight", {"Every sample's weight f |cos| / pdf against f() and pdf() at its wi (2^-12 relative; samples at "
                     "f's and pdf's float resolution excused, counted, and at most 2^-10 of the random inputs'); wi a unit vector on its flags' side; no "
                     "sample where pdf or f is 0.", ""}},
    {"bsdf_delta", {"Each delta lobe's share of draws against the probability its samples claim (exact binomial), and "
                    "its direction (mirror, Snell) and eta within float rounding.",
                    "The smallest lobe's p-value, \u0160id\u00e1k-corrected over the lobes tested."}},
    {"bsdf_albedo", {"The mean weight against the directional albedo (the integral of f |cos| plus the delta lobes), "
                     "and the energy albedo against 1 (energy created fails).",
                     "The t-test's two-sided p-value; where f's float noise reaches half its integral (no albedo "
                     "known), the one-sided p-value of the mean energy weight against 1."}},
    {"bsdf_reciprocity", {"f(wo, wi) against f(wi, wo) (the eta\u00b2 rule across an interface) at every sampled wi "
                          "and a Fibonacci grid, within 2^-12 relative or f's float resolution.", ""}},
    {"bsdf_expectation",
     {"A stochastic BSDF in expectation: the sampled weights that land in each cell of the sphere against the "
      "integral of its estimated f |cos| over the cell (z-tests with both sides' measured variances; cells judged "
      "alone where pilots promise 50 effective terms, the others pooled), the total, energy at most 1, and the MIS "
      "pdf positive at every sampled direction.",
      "1 \u2212 (1 \u2212 min p)^k, \u0160id\u00e1k over the k comparisons; a retested one's p is the larger of "
      "its two."}},
    {"bsdf_spectral",
     {"A spectral BSDF's channel case: at every sample, each secondary channel's f and pdf against f() and pdf() "
      "at its wi (a pdf of 0: terminated), each in the hero's proportion that f() and pdf() give there, within "
      "2^-12 relative.",
      ""}},
    {"bsdf_energy", {"The mean energy weight of the samples against 1, without quadrature (run by --fuzz).",
                     "The one-sided t-test's p-value of the mean energy weight above 1."}},
};

}  // namespace

std::optional<double> closeness(const CheckResult& r) {
    const RowMargin m = row_margin(r);
    std::optional<double> c;
    if (m.p_over_level) c = *m.p_over_level > 0.0 ? 1.0 / *m.p_over_level : HUGE_VAL;
    if (m.of_tolerance && (!c || *m.of_tolerance > *c || std::isnan(*m.of_tolerance))) c = *m.of_tolerance;
    if (c && std::isnan(*c)) c = HUGE_VAL;  // NaN is the worst
    return c;
}

CheckLegend check_legend(std::string_view check) {
    for (const auto& [name, legend] : kLegends)
        if (name == check) return legend;
    return {};
}

}  // namespace warpcheck::html
