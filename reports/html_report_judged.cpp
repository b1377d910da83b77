// What each check judges, read from its result: the judged quantities against
// their limits, the legend of its p-value, and what the report draws into its
// plots. The figure names are the checks' own (validate/checks/*.cpp); a
// figure that is missing leaves its line or mark out, never a wrong number.
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

using State = JudgedLine::State;

std::string general(double v) {
    if (std::isfinite(v) && v == std::round(v) && std::abs(v) < 1e15) return format_grouped(v);
    return std::isfinite(v) ? fmt::format("{:.3g}", v) : format_number(v);
}

std::string probability(double p) { return std::isnan(p) ? "NaN" : format_probability(p); }

/// A line `value >= limit` for a p-value (NaN is below every limit).
JudgedLine p_line(std::string quantity, double p, double limit, const std::string& limit_note) {
    return {std::move(quantity), probability(p), fmt::format("\u2265 {}{}", format_probability(limit), limit_note),
            p >= limit ? State::Within : State::Beyond};
}

/// How a figure is judged in the table-driven rules below.
enum class Rule {
    Zero,         ///< a count that must be 0
    AtMost,       ///< at most the figure `limit`
    WithinOfOne,  ///< |value - 1| at most the figure `limit`
    Counted,      ///< reported, not judged (an excuse or a note)
};

struct Spec {
    const char* figure;
    const char* quantity;
    Rule rule;
    const char* limit = "";
};

/// The figures each check judges (or reports beside its verdict), in its own words.
const std::vector<std::pair<std::string_view, std::vector<Spec>>> kSpecs = {
        {"consistency",
         {{"non_finite_samples", "samples with NaN or infinite coordinates", Rule::Zero},
          {"outside_domain", "samples outside the domain", Rule::Zero},
          {"non_finite_or_negative_pdf", "samples with a NaN, infinite or negative pdf", Rule::Zero},
          {"zero_pdf", "samples with pdf 0 inside the domain", Rule::Zero},
          {"zero_pdf_on_boundary", "samples with pdf 0 on the boundary (allowed)", Rule::Counted},
          {"zero_pdf_rounded_random", "random samples with pdf 0 beside a positive pdf (float rounding; any fails under --strict)",
           Rule::AtMost, "zero_pdf_rounded_bound"},
          {"zero_pdf_rounded_edge_inputs", "edge inputs with pdf 0 beside a positive pdf", Rule::Counted}}},
        {"roundtrip",
         {{"max_error", "largest |invert(sample(u)) \u2212 u| not excused", Rule::AtMost, "tolerance"},
          {"failures", "inputs beyond the tolerance, not excused", Rule::Zero},
          {"outside_input_domain", "inverses outside [0, 1)", Rule::Zero},
          {"other_preimage_random_inputs", "random inputs with another preimage", Rule::AtMost, "other_preimage_bound"},
          {"float_pole_random_inputs", "random inputs at a float pole", Rule::AtMost, "float_pole_bound"},
          {"resolution_limited", "resolution-limited inputs (excused)", Rule::Counted},
          {"degenerate", "degenerate inputs (excused)", Rule::Counted},
          {"rounded_to_one", "u rounded to 1 (excused; fails under --strict)", Rule::Counted}}},
        {"exhaustive_roundtrip",
         {{"max_error", "largest |invert(sample(u)) \u2212 u|", Rule::AtMost, "tolerance"},
          {"roundtrip_failures", "floats beyond the tolerance", Rule::Zero},
          {"bad_pdf", "samples with a pdf that is not finite and positive", Rule::Zero},
          {"max_step_back_ulps", "largest step back of sample(u), ulps", Rule::AtMost, "wobble_tolerance_ulps"},
          {"outside_input_domain", "inverses outside [0, 1)", Rule::Zero},
          {"rounded_to_one", "u rounded to 1 (excused; fails under --strict)", Rule::Counted}}},
        {"exhaustive",
         {{"outside_inputs", "inputs whose output is outside [a, b)", Rule::Zero},
          {"mass_outside_reach", "ideal mass outside the outputs' reach", Rule::AtMost, "reach_allowance"},
          {"non_monotone_steps", "steps down (fail if the sampler claims to be monotone)", Rule::Counted},
          {"max_float_bias", "largest float bias factor (fails only beyond --max-float-bias)", Rule::Counted},
          {"unreached_above_one_input", "floats never produced whose ideal exceeds one input", Rule::Counted}}},
        {"tabulated",
         {{"x_failures", "samples beyond the x tolerance", Rule::Zero},
          {"pdf_failures", "pdfs beyond the pdf tolerance", Rule::Zero},
          {"tail_failures", "tail samples beyond the table's reach", Rule::Zero},
          {"nan_samples", "NaN samples", Rule::Zero},
          {"nan_pdfs", "NaN pdfs", Rule::Zero},
          {"mass_outside_reach", "mass outside the warp's reach", Rule::AtMost, "mass_outside_reach_tolerance"}}},
        {"chi2",
         {{"integral", "integral of the density over the domain", Rule::WithinOfOne, "integral_tolerance"},
          {"outside", "samples outside the domain", Rule::Zero},
          {"nan", "samples with NaN coordinates", Rule::Zero},
          {"zero_expected_hits", "samples in cells of expected count 0", Rule::Zero},
          {"pooled_cells", "cells pooled (expected count below 5)", Rule::Counted}}},
        {"pmf",
         {{"sum", "sum of the pmf", Rule::WithinOfOne, "tolerance"},
          {"invalid", "NaN, infinite or negative entries", Rule::Zero}}},
        {"sample_pdf",
         {{"max_relative_difference", "largest relative difference", Rule::AtMost, "tolerance"},
          {"mismatches", "samples beyond the tolerance", Rule::Zero}}},
        {"weight",
         {{"max_relative_difference", "largest relative difference", Rule::AtMost, "tolerance"},
          {"mismatches", "samples beyond the tolerance", Rule::Zero}}},
        {"weight_mean", {{"invalid_samples", "samples with a non-finite weight", Rule::Zero}}},
        {"inverse_pdf_mean", {{"invalid_samples", "samples with a non-finite 1/pdf", Rule::Zero}}},
        {"binade", {{"outside", "samples outside [a, b)", Rule::Zero}}},
        {"discrete_chi2",
         {{"outside", "samples that are not a category", Rule::Zero},
          {"zero_pmf_chosen", "categories of pmf 0 chosen", Rule::Zero}}},
        {"remapped_u", {{"outside", "remapped u outside [0, 1)", Rule::Zero}}},
        {"bsdf_chi2",
         {{"outside", "continuous samples off the sphere", Rule::Zero},
          {"nan", "continuous samples with NaN coordinates", Rule::Zero},
          {"zero_expected_hits", "continuous samples in cells where pdf(wo, .) integrates to 0", Rule::Zero},
          {"reintegrated_cells", "cells integrated again around samples", Rule::Counted}}},
        {"bsdf_weight",
         {{"max_relative_difference", "largest relative weight difference, not excused", Rule::AtMost, "tolerance"},
          {"max_unit_error", "largest ||wi| − 1|", Rule::AtMost, "unit_tolerance"},
          {"weight_mismatches", "samples whose weight differs beyond the tolerance", Rule::Zero},
          {"not_unit", "samples whose wi is not a unit vector", Rule::Zero},
          {"wrong_side", "samples on the wrong side for their flags", Rule::Zero},
          {"zero_pdf", "continuous samples where pdf(wo, wi) is 0", Rule::Zero},
          {"zero_f", "continuous samples where f(wo, wi) is 0", Rule::Zero},
          {"bad_delta", "delta samples with a weight not finite and positive", Rule::Zero},
          {"wrong_eta", "continuous transmissions whose eta is not the case's", Rule::Zero},
          {"excused", "samples at the float resolution of f and pdf (excused)", Rule::Counted},
          {"excused_random", "of them, from random inputs", Rule::AtMost, "excused_random_limit"},
          {"excused_outside_support", "of them, where f or pdf at wi is 0 (a neighbour's is not)", Rule::Counted}}},
        {"bsdf_expectation",
         {{"bad_weights", "draws whose weight is not finite or negative", Rule::Zero},
          {"bad_directions", "draws whose wi is not a unit vector", Rule::Zero},
          {"off_side_samples", "continuous draws on a side the lobes do not claim", Rule::Zero},
          {"mis_pdf_zero_samples", "continuous draws where pdf(wo, wi) is not positive", Rule::Zero},
          {"cells_pooled", "cells pooled into the remainder (pilots promised too few terms)", Rule::Counted},
          {"cells_retested", "comparisons retested against a 16 times larger reference", Rule::Counted},
          {"cells_excused", "cells excused (their remainder too sparse to judge)", Rule::Counted}}},
        {"bsdf_spectral",
         {{"bad_values", "channel values not finite or negative", Rule::Zero},
          {"f_mismatches", "secondary channels' f beyond the tolerance", Rule::Zero},
          {"pdf_mismatches", "secondary channels' pdf beyond the tolerance", Rule::Zero},
          {"hero_mismatches", "hero samples unlike the spectral sample's hero channel", Rule::Zero},
          {"max_f_relative_difference", "largest relative difference of a secondary f", Rule::Counted},
          {"terminated", "secondary channels terminated (pdf 0)", Rule::Counted},
          {"compared_without_ratio", "secondary values compared without a ratio (a hero value of 0)",
           Rule::Counted}}},
        {"bsdf_delta",
         {{"off_direction", "delta samples off their mirror or Snell direction", Rule::Zero},
          {"wrong_eta", "delta samples whose eta is not the case's", Rule::Zero}}},
        {"bsdf_reciprocity",
         {{"max_relative_error", "largest relative error |f(wo, wi) s − f(wi, wo)|, not excused", Rule::AtMost,
           "tolerance"},
          {"violations", "pairs beyond the tolerance", Rule::Zero},
          {"excused_pairs", "pairs at f's float resolution (excused)", Rule::Counted},
          {"grid_excused_pairs", "of them, on the evenly spread grid", Rule::AtMost, "grid_excused_pairs_bound"}}},
};

const std::vector<Spec>& specs_of(std::string_view check) {
    static const std::vector<Spec> none;
    for (const auto& [name, specs] : kSpecs)
        if (name == check) return specs;
    return none;
}

std::optional<JudgedLine> spec_line(const CheckResult& r, const Spec& s) {
    const auto value = r.figure(s.figure);
    if (!value) return std::nullopt;
    const auto limit = *s.limit ? r.figure(s.limit) : std::nullopt;
    switch (s.rule) {
        case Rule::Zero:
            return JudgedLine{s.quantity, general(*value), "= 0", *value == 0.0 ? State::Within : State::Beyond};
        case Rule::AtMost:
            if (!limit || (*limit == 0.0 && std::string_view(s.limit) == "tolerance")) return std::nullopt;  // exact rules count failures
            return JudgedLine{s.quantity, general(*value), "\u2264 " + general(*limit),
                              *value <= *limit ? State::Within : State::Beyond};
        case Rule::WithinOfOne:
            if (!limit) return std::nullopt;
            return JudgedLine{s.quantity, fmt::format("{:.9g}", *value), "|x \u2212 1| \u2264 " + general(*limit),
                              std::abs(*value - 1.0) <= *limit ? State::Within : State::Beyond};
        case Rule::Counted: return JudgedLine{s.quantity, general(*value), "counted", State::Reported};
    }
    return std::nullopt;
}

// ---- the p-values of statistical checks -----------------------------------

constexpr double kLocalShare = kChi2LocalShare;

bool same(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)); }

void chi2_p_lines(const CheckResult& r, double level, std::vector<JudgedLine>& out) {
    const auto pearson = r.figure("p_value"), local = r.figure("local_p_value");
    if (!pearson || !local || !r.p_value) return;
    const double combined = std::min({1.0, *pearson / (1.0 - kLocalShare), *local / kLocalShare});
    if (!same(combined, *r.p_value)) return;  // another rule than this file knows: show the p-value alone
    out.push_back(p_line(fmt::format("Pearson X\u00b2 = {:.4g} on {} dof: p-value", r.figure("statistic").value_or(NAN),
                                     general(r.figure("dof").value_or(NAN))),
                         *pearson, (1.0 - kLocalShare) * level, fmt::format(" ({} \u00d7 level)", 1.0 - kLocalShare)));
    const auto cell = ringed_cell(r);
    out.push_back(p_line(fmt::format("largest cell residual {:+.2f} (cell {}): p-value over the cells",
                                     cell ? cell->residual : NAN,
                                     cell ? general(static_cast<double>(cell->index)) : format_number(NAN)),
                         *local, kLocalShare * level, fmt::format(" ({} \u00d7 level)", kLocalShare)));
}

/// bsdf_chi2's three tests, each at its share of the level: Pearson's 0.7,
/// the largest residual's 0.2, the landing share's 0.1 (weighted Bonferroni).
void bsdf_chi2_p_lines(const CheckResult& r, double level, std::vector<JudgedLine>& out) {
    const auto pearson = r.figure("pearson_p_value"), local = r.figure("local_p_value"),
               landing = r.figure("landing_p_value");
    if (!pearson || !local || !landing || !r.p_value) return;
    const double combined = std::min({1.0, *pearson / 0.7, *local / kLocalShare, *landing / 0.1});
    if (!same(combined, *r.p_value)) return;
    out.push_back(p_line(fmt::format("Pearson X\u00b2 = {:.4g} on {} dof: p-value", r.figure("statistic").value_or(NAN),
                                     general(r.figure("dof").value_or(NAN))),
                         *pearson, 0.7 * level, " (0.7 \u00d7 level)"));
    const auto cell = ringed_cell(r);
    out.push_back(p_line(fmt::format("largest cell residual {:+.2f}: p-value over the cells",
                                     cell ? cell->residual : NAN),
                         *local, kLocalShare * level, fmt::format(" ({} \u00d7 level)", kLocalShare)));
    out.push_back(p_line(fmt::format("share of draws that landed ({} of {}): binomial p-value",
                                     general(r.figure("continuous_samples").value_or(NAN)),
                                     general(r.figure("samples").value_or(NAN) - r.figure("delta_samples").value_or(0.0))),
                         *landing, 0.1 * level, " (0.1 \u00d7 level)"));
}

/// The rules of the BSDF checks that compare two figures: pdf(wo, .)'s
/// integral against what the continuous lobes hold, the energy albedo against 1.
void bsdf_bound_lines(const CheckResult& r, std::vector<JudgedLine>& out) {
    const auto integral = r.figure("pdf_integral"), tolerance = r.figure("integral_tolerance"),
               delta = r.figure("delta_claimed");
    if (r.check_name == "bsdf_chi2" && integral && tolerance && delta) {
        const double room = 1.0 - *delta + *tolerance;
        out.push_back({"pdf(wo, .) integrated over the sphere", fmt::format("{:.9g}", *integral),
                       fmt::format("\u2264 1 \u2212 {} (delta lobes) + {}", general(*delta), general(*tolerance)),
                       *integral <= room ? State::Within : State::Beyond});
    }
    const auto energy = r.figure("energy_albedo"), bound = r.figure("energy_tolerance");
    if (r.check_name == "bsdf_albedo" && energy && bound && r.figure("albedo_known").value_or(1.0) != 0.0)
        out.push_back({"energy albedo", fmt::format("{:.9g}", *energy), "\u2264 1 + " + general(*bound),
                       *energy <= 1.0 + *bound ? State::Within : State::Beyond});
}

/// "cos theta" -> "cos_theta", as the unbinned check names its figures.
std::string figure_label(const std::string& label) {
    std::string s;
    for (char ch : label) s += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return s;
}

std::string test_name(std::string_view short_name) {
    if (short_name == "ad") return "Anderson\u2013Darling A\u00b2";
    if (short_name == "kuiper") return "Kuiper V";
    if (short_name == "ks") return "Kolmogorov\u2013Smirnov D";
    return std::string(short_name);
}

void unbinned_p_lines(const CheckResult& r, double level, std::vector<JudgedLine>& out) {
    const auto judged = judged_unbinned_tests(r);
    const double k = r.figure("tests").value_or(static_cast<double>(judged.size()));
    if (judged.empty() || !(k >= 1.0)) return;
    const double per_marginal = -std::expm1(std::log1p(-level) / k);  // Sidak: 1 - (1 - level)^(1/k)
    for (const auto& [marginal, test] : judged) {
        const std::string name = figure_label(marginal) + "_" + test;
        const auto p = r.figure(name + "_p_value");
        if (!p) continue;
        out.push_back(p_line(fmt::format("{}: {} = {:.4g}, p-value", marginal, test_name(test),
                                         r.figure(name + "_statistic").value_or(NAN)),
                             *p, per_marginal, fmt::format(" (level, \u0160id\u00e1k over {})", general(k))));
    }
}

/// Two tests of one check, each at its share of the level (Bonferroni).
void shared_p_lines(const CheckResult& r, double level, std::vector<JudgedLine>& out,
                    std::vector<std::pair<const char*, const char*>> tests) {
    std::erase_if(tests, [&](const auto& t) { return !r.figure(t.first) || std::isnan(*r.figure(t.first)); });
    if (tests.size() < 2) return;
    const double share = 1.0 / static_cast<double>(tests.size());
    for (const auto& [figure, quantity] : tests)
        out.push_back(p_line(quantity, *r.figure(figure), share * level, fmt::format(" (level / {})", tests.size())));
}

/// The checks whose p-value is the unbinned check's (bsdf_unbinned runs its engine).
bool unbinned_like(std::string_view check) { return check == "unbinned" || check == "bsdf_unbinned"; }

std::string combined_name(std::string_view check) {
    if (check == "chi2") return "p-value: min(Pearson / 0.8, residual / 0.2), at most 1";
    if (check == "bsdf_chi2") return "p-value: min(Pearson / 0.7, residual / 0.2, landing / 0.1), at most 1";
    if (unbinned_like(check)) return "p-value: smallest judged p, \u0160id\u00e1k-corrected over the judged tests";
    if (check == "bsdf_delta") return "p-value: the smallest lobe's, \u0160id\u00e1k-corrected over the lobes tested";
    if (check == "bsdf_expectation")
        return "p-value: the smallest of the cells', remainder's, total's and energy's, \u0160id\u00e1k-corrected";
    if (check == "binade" || check == "remapped_u") return "p-value: the smallest test's, times the number of tests, at most 1";
    return "p-value";
}

void p_value_lines(const CheckResult& r, std::vector<JudgedLine>& out) {
    if (!r.p_value) return;
    if (!r.level) {
        out.push_back({"p-value", probability(*r.p_value), "no level applied", State::Reported});
        return;
    }
    const double level = *r.level;
    if (r.check_name == "chi2") chi2_p_lines(r, level, out);
    if (r.check_name == "bsdf_chi2") bsdf_chi2_p_lines(r, level, out);
    if (unbinned_like(r.check_name)) unbinned_p_lines(r, level, out);
    if (r.check_name == "binade")
        shared_p_lines(r, level, out, {{"mass_p_value", "mass per binade: Pearson p-value"},
                                       {"parity_p_value", "significand parity: Pearson p-value"},
                                       {"resolution_p_value", "binary digits of (x \u2212 a) / (b \u2212 a): p-value"}});
    if (r.check_name == "remapped_u")
        shared_p_lines(r, level, out, {{"ks_p_value", "remapped u: KS p-value"},
                                       {"conditional_p_value", "u within each category: Pearson p-value"}});
    out.push_back(p_line(combined_name(r.check_name), *r.p_value, level, " (per-test level)"));
}

/// Every `*_over_tolerance` figure and every `X` beside an `X_tolerance` that
/// no rule above took: the generic margin rules of the terminal table.
void tolerance_lines(const CheckResult& r, const std::set<std::string>& used, std::vector<JudgedLine>& out) {
    for (const Figure& f : r.figures) {
        if (used.count(f.name)) continue;
        if (f.name.ends_with("_over_tolerance")) {
            out.push_back({f.name, general(f.value), "\u2264 1", f.value <= 1.0 ? State::Within : State::Beyond});
        } else if (const auto tol = r.figure(f.name + "_tolerance"); tol && !used.count(f.name + "_tolerance")) {
            const bool integral = f.name.ends_with("integral");
            const double error = integral ? std::abs(f.value - 1.0) : std::abs(f.value);
            out.push_back({f.name, general(f.value), (integral ? "|x \u2212 1| \u2264 " : "|x| \u2264 ") + general(*tol),
                           error <= *tol ? State::Within : State::Beyond});
        }
    }
}

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

std::vector<std::pair<std::string, std::string>> judged_unbinned_tests(const CheckResult& r) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const Table& t : r.tables) {
        const auto at = [&](std::string_view c) { return std::find(t.columns.begin(), t.columns.end(), c) - t.columns.begin(); };
        const auto m = at("marginal"), test = at("test"), judged = at("judged");
        const auto n = static_cast<std::ptrdiff_t>(t.columns.size());
        if (m == n || test == n || judged == n) continue;
        for (const auto& row : t.rows)
            if (static_cast<std::ptrdiff_t>(row.size()) == n && row[static_cast<std::size_t>(judged)] == "yes")
                out.emplace_back(row[static_cast<std::size_t>(m)], row[static_cast<std::size_t>(test)]);
    }
    return out;
}

std::vector<JudgedLine> judged_lines(const CheckResult& r) {
    std::vector<JudgedLine> out;
    p_value_lines(r, out);
    bsdf_bound_lines(r, out);
    std::set<std::string> used;
    for (const Spec& s : specs_of(r.check_name)) {
        if (auto line = spec_line(r, s)) {
            out.push_back(std::move(*line));
            used.insert(s.figure);
            if (*s.limit) used.insert(s.limit);
        }
    }
    tolerance_lines(r, used, out);
    return out;
}

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
