// The checks of discrete samplers (an index out of WarpCaseInfo::categories,
// with a pmf), as a renderer picks a light, a lobe or a table entry:
//   pmf:           the pmf is finite, non-negative and sums to 1;
//   discrete_chi2: every index is a category, no category of pmf 0 is ever
//                  chosen, and the counts per category fit the pmf (Pearson,
//                  small categories pooled, in the run's family);
//   remapped_u:    the u that a sampler returns for reuse (DiscreteSample) lies
//                  in [0,1) and is uniform, overall (Kolmogorov-Smirnov),
//                  within each category (chi-square over 16 bins per category)
//                  and at every resolution down to 2^-20 (chi2/resolution_test.h:
//                  a u cut to 10 bits passes the other two).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "chi2/min_p.h"
#include "chi2/pearson.h"
#include "chi2/resolution_test.h"
#include "chi2/unbinned.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/formatting.h"
#include "validate/checks/shared/input_chunks.h"

namespace warpcheck {
namespace {

/// pmf(k) for every category k.
std::vector<double> pmf_of(const WarpCase& warp) {
    const std::size_t n = warp.info().categories;
    std::vector<WarpOutput> index(n);
    for (std::size_t k = 0; k < n; ++k) index[k] = {static_cast<float>(k), 0.0f, 0.0f};
    std::vector<double> pmf(n);
    warp.pdf(index, pmf);
    return pmf;
}

/// The category of an output, or -1 when it is none (NaN, negative, fractional, too large).
std::ptrdiff_t category_of(const WarpOutput& o, std::size_t categories) {
    const float v = o[0];
    if (!(v >= 0.0f && v < static_cast<float>(categories)) || v != std::floor(v)) return -1;
    return static_cast<std::ptrdiff_t>(v);
}

bool is_discrete_case(const WarpCase& warp) { return warp.is_discrete() && warp.has_pdf(); }

// ---- pmf -------------------------------------------------------------------

class PmfCheck final : public Check {
public:
    std::string name() const override { return "pmf"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"sum", "sum of the pmf", FigureRule::WithinOfOne, "tolerance"},
                 {"invalid", "NaN, infinite or negative entries", FigureRule::Zero}}};
    }
    CheckLegend legend() const override {
        return {name(), "The pmf is finite, non-negative and sums to 1 within float rounding.",
                ""};
    }
    std::string description() const override {
        return "discrete cases: the pmf is finite, non-negative and sums to 1 over the categories";
    }
    Applicability applicability(const WarpCase& warp) const override {
        return Applicability::when(is_discrete_case(warp));
    }
    bool uses_seed() const override { return false; }

    CheckResult run(const WarpCase& warp, const CheckContext&) const override {
        const std::vector<double> pmf = pmf_of(warp);
        const std::size_t n = pmf.size();
        double sum = 0.0;
        std::size_t bad = 0, zero = 0, first_bad = n;
        for (std::size_t k = 0; k < n; ++k) {
            if (!(std::isfinite(pmf[k]) && pmf[k] >= 0.0)) bad += 1, first_bad = std::min(first_bad, k);
            else zero += pmf[k] == 0.0;
            sum += pmf[k];
        }
        // Float probabilities w_k / W carry the rounding of W, a float sum of n
        // weights (relative error up to n 2^-24), plus half an ulp each: they sum
        // to 1 within (n + 1) 2^-24; a wrong normaliser is off by far more.
        const double tolerance = static_cast<double>(n + 1) * 0x1p-24;
        CheckResult r;
        r.figures = {{"categories", static_cast<double>(n)}, {"sum", sum},        {"tolerance", tolerance},
                     {"invalid", static_cast<double>(bad)},  {"zero", static_cast<double>(zero)}};
        r.summary = fmt::format("sum {:.9g} over {} categories ({} of pmf 0)", sum, n, zero);
        r.verdict = Verdict::Pass;
        if (bad > 0) {
            r.verdict = Verdict::Fail;
            r.message = fmt::format("{} categories have a NaN, infinite or negative pmf (first: {} with {:.6g})", bad,
                                    first_bad, pmf[first_bad]);
        } else if (!(std::abs(sum - 1.0) <= tolerance)) {
            r.verdict = Verdict::Fail;
            r.message = fmt::format("the pmf sums to {:.9g}, not 1 (tolerance {:.3g})", sum, tolerance);
        }
        if (r.verdict == Verdict::Fail) r.summary = r.message.substr(0, r.message.find(" ("));
        return r;
    }
};

// ---- discrete_chi2 ---------------------------------------------------------

struct Example {
    WarpInput input;
    WarpOutput output{};
};

struct Tallies {
    Tally<Example> outside, zero_chosen;
    void merge(const Tallies& o) {
        outside.merge(o.outside);
        zero_chosen.merge(o.zero_chosen);
    }
};

struct Counted {
    std::vector<double> counts;  ///< per category, random inputs only
    Tallies tallies;             ///< edge inputs included
};

/// Counts the samples per category. Integer counts add in any order, so the
/// shared atomic counters give the same numbers for any thread count.
Counted count_categories(const WarpCase& warp, const CheckContext& ctx, const std::vector<double>& pmf) {
    const std::size_t n = pmf.size();
    std::vector<std::atomic<uint64_t>> counts(n);
    auto parts = map_input_chunks<Tallies>(ctx, warp.input_kind(), ctx.options().samples, true,
                                           [&](std::size_t chunk, std::span<const WarpInput> inputs) {
        std::vector<WarpOutput> x(inputs.size());
        warp.sample(inputs, x);
        Tallies t;
        for (std::size_t i = 0; i < inputs.size(); ++i) {
            const std::ptrdiff_t k = category_of(x[i], n);
            const uint64_t index = chunk * kInputChunkSize + i;
            if (k < 0) t.outside.add(index, {inputs[i], x[i]});
            else if (pmf[static_cast<std::size_t>(k)] == 0.0) t.zero_chosen.add(index, {inputs[i], x[i]});
            if (k >= 0 && chunk > 0) counts[static_cast<std::size_t>(k)].fetch_add(1, std::memory_order_relaxed);
        }
        return t;
    });
    Counted c{std::vector<double>(n), merge_in_order(parts)};
    for (std::size_t k = 0; k < n; ++k) c.counts[k] = static_cast<double>(counts[k].load());
    return c;
}

std::string first_example(const Tally<Example>& t, InputKind kind) {
    return fmt::format("e.g. u = {} -> {}", format_input(t.first->input, kind), t.first->output[0]);
}

Plot counts_plot(const std::vector<double>& observed, const std::vector<double>& expected, const std::string& name) {
    Plot p;
    p.kind = Plot::Kind::Bars;
    p.title = "samples per category of " + name;
    p.x_label = "category";
    p.y_label = "samples";
    std::vector<double> x(observed.size());
    for (std::size_t k = 0; k < x.size(); ++k) x[k] = static_cast<double>(k);
    p.series = {{"observed", x, observed}, {"expected", x, expected}};
    return p;
}

class DiscreteChi2Check final : public Check {
public:
    std::string name() const override { return "discrete_chi2"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"outside", "samples that are not a category", FigureRule::Zero},
                 {"zero_pmf_chosen", "categories of pmf 0 chosen", FigureRule::Zero}}};
    }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "Pearson's X\u00b2 of the category counts against the pmf; a category of pmf 0 chosen fails.",
                "Pearson's p-value."};
    }
    std::string description() const override {
        return "discrete cases: indices are categories, none of pmf 0 is chosen, and the counts fit the pmf "
               "(Pearson, pooled, Sidak-corrected)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        return Applicability::when(is_discrete_case(warp));
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const std::vector<double> pmf = pmf_of(warp);
        const Counted c = count_categories(warp, ctx, pmf);
        CheckResult r;
        r.samples = ctx.options().samples;
        judge(r, c, pmf, warp.input_kind());
        if (pmf.size() <= 256) {
            std::vector<double> expected = expected_counts(pmf, static_cast<double>(r.samples));
            r.plots.push_back(counts_plot(c.counts, expected, warp.name()));
        }
        return r;
    }

private:
    /// N pmf(k) / sum of pmf: the fit is judged apart from the normalisation (the pmf check's).
    static std::vector<double> expected_counts(const std::vector<double>& pmf, double samples) {
        double sum = 0.0;
        for (double p : pmf) sum += p;
        std::vector<double> e(pmf.size());
        for (std::size_t k = 0; k < pmf.size(); ++k) e[k] = samples * pmf[k] / sum;
        return e;
    }

    static void judge(CheckResult& r, const Counted& c, const std::vector<double>& pmf, InputKind kind) {
        const std::vector<double> expected = expected_counts(pmf, static_cast<double>(r.samples));
        std::vector<double> observed, used;  // categories of pmf 0 are judged by the rule below, not by Pearson
        std::size_t invalid = 0;
        for (std::size_t k = 0; k < pmf.size(); ++k) {
            if (pmf[k] > 0.0 && std::isfinite(pmf[k])) observed.push_back(c.counts[k]), used.push_back(expected[k]);
            invalid += !(pmf[k] >= 0.0 && std::isfinite(pmf[k]));
        }
        const chi2::PearsonResult p = chi2::pearson_test(observed, used);
        r.figures = {{"statistic", p.statistic}, {"dof", static_cast<double>(p.dof)},
                     {"p_value", p.p_value},     {"pooled_categories", static_cast<double>(p.small_cells)},
                     {"outside", static_cast<double>(c.tallies.outside.count)},
                     {"zero_pmf_chosen", static_cast<double>(c.tallies.zero_chosen.count)},
                     {"invalid_pmf", static_cast<double>(invalid)}};
        // With fewer than two categories of positive pmf the counts have no
        // degrees of freedom: only the indices are tested, and the row says so.
        r.summary = p.dof >= 1 ? fmt::format("chi2 {:.1f} dof {} p {:.3g}", p.statistic, p.dof, p.p_value)
                               : fmt::format("indices only: {} category of positive pmf, no degrees of freedom",
                                             observed.size());
        r.verdict = Verdict::Pass;
        if (p.dof >= 1) r.p_value = p.p_value;
        std::vector<std::string> problems;
        // The counts cannot be judged against a pmf that is not a pmf (the pmf check names the categories).
        if (invalid > 0)
            problems.push_back(fmt::format("{} of {} categories have a NaN, infinite or negative pmf: the counts "
                                           "cannot be tested against it",
                                           invalid, pmf.size()));
        else if (observed.empty())
            problems.push_back("no category has a positive pmf: the counts cannot be tested against it");
        if (c.tallies.outside.count > 0)
            problems.push_back(fmt::format("{} samples are not a category of 0..{} ({})", c.tallies.outside.count,
                                           pmf.size() - 1, first_example(c.tallies.outside, kind)));
        if (c.tallies.zero_chosen.count > 0)
            problems.push_back(fmt::format("{} samples chose a category of pmf 0 ({})", c.tallies.zero_chosen.count,
                                           first_example(c.tallies.zero_chosen, kind)));
        if (problems.empty()) return;
        r.verdict = Verdict::Fail;
        r.summary = problems.front().substr(0, problems.front().find(" ("));
        r.message = join_reasons(problems);
    }
};

// ---- remapped_u ------------------------------------------------------------

/// Bins of the remapped u per category in the conditional test: 16 sees a
/// remapping that is off by a slope or a shift inside each category.
constexpr std::size_t kRemapBins = 16;
/// The conditional table is kept below 2^22 cells (32 MiB of counters).
constexpr std::size_t kMaxRemapCells = std::size_t{1} << 22;

struct RemapPart {
    std::vector<double> u;  ///< remapped u of the random inputs
    Tally<Example> outside;
    void merge(const RemapPart& o) {
        u.insert(u.end(), o.u.begin(), o.u.end());
        outside.merge(o.outside);
    }
};

RemapPart collect_remapped(const WarpCase& warp, const CheckContext& ctx, std::vector<std::atomic<uint64_t>>& table) {
    const std::size_t n = warp.info().categories;
    auto parts = map_input_chunks<RemapPart>(ctx, warp.input_kind(), ctx.options().samples, true,
                                             [&](std::size_t chunk, std::span<const WarpInput> inputs) {
        std::vector<WarpOutput> x(inputs.size());
        std::vector<double> u(inputs.size());
        warp.sample_with_value(inputs, x, u);
        RemapPart part;
        for (std::size_t i = 0; i < inputs.size(); ++i) {
            if (!(u[i] >= 0.0 && u[i] < 1.0)) {
                part.outside.add(chunk * kInputChunkSize + i, {inputs[i], {static_cast<float>(u[i]), 0.0f, 0.0f}});
                continue;
            }
            if (chunk == 0) continue;  // edge inputs are not uniform: only their range is checked
            part.u.push_back(u[i]);
            const std::ptrdiff_t k = category_of(x[i], n);
            if (k >= 0 && !table.empty()) {
                const auto bin = static_cast<std::size_t>(u[i] * kRemapBins);
                table[static_cast<std::size_t>(k) * kRemapBins + bin].fetch_add(1, std::memory_order_relaxed);
            }
        }
        return part;
    });
    return merge_in_order(parts);
}

/// Pearson's test of the (category, u bin) table against N pmf(k) / 16 per cell.
chi2::PearsonResult conditional_test(const std::vector<std::atomic<uint64_t>>& table, const std::vector<double>& pmf,
                                     double samples) {
    double sum = 0.0;
    for (double p : pmf) sum += p;
    std::vector<double> observed, expected;
    for (std::size_t k = 0; k < pmf.size(); ++k) {
        if (!(pmf[k] > 0.0)) continue;
        for (std::size_t b = 0; b < kRemapBins; ++b) {
            observed.push_back(static_cast<double>(table[k * kRemapBins + b].load()));
            expected.push_back(samples * pmf[k] / sum / kRemapBins);
        }
    }
    return chi2::pearson_test(observed, expected);
}

/// The digits of the remapped u tested for resolution: down to 2^-20
/// (chi2::kResolutionDigits), but no finer than a remap of a float u can keep:
/// choosing one of n categories uses ceil(log2 n) of the 24 bits that u has in
/// [0.5, 1) (pbrt's alias table rounds u n to a float, whose spacing there is
/// 2^-(24 - ceil(log2 n))), so a correct remap keeps 24 - ceil(log2 n).
int remap_digits(std::size_t categories) {
    int used = 0;
    while ((std::size_t{1} << used) < categories) ++used;
    return std::clamp(24 - used, 1, chi2::kResolutionDigits);
}

Plot remapped_histogram(const std::vector<double>& sorted_u, const std::string& name) {
    Plot p;
    p.kind = Plot::Kind::Bars;
    p.title = "remapped u of " + name;
    p.x_label = "remapped u";
    p.y_label = "samples per 1/64";
    std::vector<double> x(64), y(64, 0.0);
    for (std::size_t b = 0; b < 64; ++b) x[b] = (static_cast<double>(b) + 0.5) / 64.0;
    for (double u : sorted_u) y[std::min<std::size_t>(63, static_cast<std::size_t>(u * 64.0))] += 1.0;
    p.series = {{"observed", x, y}, {"expected", x, std::vector<double>(64, static_cast<double>(sorted_u.size()) / 64)}};
    return p;
}

class RemappedUCheck final : public Check {
public:
    std::string name() const override { return "remapped_u"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"outside", "remapped u outside [0, 1)", FigureRule::Zero}},
                .p_values =
                    [](const CheckResult& r, double level, std::vector<JudgedQuantity>& out) {
                        shared_p_lines(r, level, out,
                                       {{"ks_p_value", "remapped u: KS p-value"},
                                        {"conditional_p_value", "u within each category: Pearson p-value"}});
                    },
                .p_value = "p-value: the smallest test's, times the number of tests, at most 1"};
    }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "The remapped u: overall KS against uniform, and a X\u00b2 of u within each category.",
                "min(p_KS / 0.5, p_X\u00b2 / 0.5) (weighted Bonferroni)."};
    }
    std::string description() const override {
        return "discrete cases returning a remapped u: it lies in [0,1) and is uniform, overall (KS), within each "
               "category (chi-square) and down to 2^-20 (binary digits), Sidak-corrected";
    }
    Applicability applicability(const WarpCase& warp) const override {
        return Applicability::when(is_discrete_case(warp) &&
                                   warp.sample_returns() == SampleReturns::IndexAndRemappedU);
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const std::vector<double> pmf = pmf_of(warp);
        const bool conditional = pmf.size() * kRemapBins <= kMaxRemapCells;
        std::vector<std::atomic<uint64_t>> table(conditional ? pmf.size() * kRemapBins : 0);
        RemapPart part = collect_remapped(warp, ctx, table);
        chi2::sort_unit_values(part.u);
        const chi2::UnbinnedStatistics ks = chi2::unbinned_statistics(part.u);
        const double ks_p = ks.p_value(chi2::UnbinnedTest::KolmogorovSmirnov);
        const chi2::ResolutionTest res = chi2::resolution_test(part.u, remap_digits(pmf.size()));
        CheckResult r;
        r.samples = part.u.size();
        r.figures = {{"ks", ks.ks()}, {"ks_p_value", ks_p}, {"outside", static_cast<double>(part.outside.count)},
                     {"resolution_digits", static_cast<double>(res.digits)},
                     {"resolution_p_value", res.p_value},
                     {"resolution_worst_digit", static_cast<double>(res.worst_digit)},
                     {"resolution_worst_ones_fraction", res.worst_ones_fraction}};
        double conditional_p = 1.0;
        bool conditional_tested = false;
        if (conditional) {
            const chi2::PearsonResult c = conditional_test(table, pmf, static_cast<double>(r.samples));
            r.figures.insert(r.figures.end(), {{"conditional_chi2", c.statistic},
                                               {"conditional_dof", static_cast<double>(c.dof)},
                                               {"conditional_p_value", c.p_value}});
            conditional_tested = c.dof >= 1;
            conditional_p = c.p_value;
        }
        // Three (or two) tests of the same samples, one p-value: weighted
        // Bonferroni, an equal share of the level each (valid whatever their
        // dependence); a NaN among them (too few samples) makes it NaN, which fails.
        const double p = conditional_tested ? chi2::weighted_min_p({ks_p, conditional_p, res.p_value},
                                                                   {1.0 / 3, 1.0 / 3, 1.0 / 3})
                                            : chi2::weighted_min_p({ks_p, res.p_value}, {0.5, 0.5});
        r.p_value = p;
        r.summary = fmt::format("KS p {:.3g}, resolution p {:.3g} (2^-{}", ks_p, res.p_value, res.digits);
        if (res.p_value < 1e-3)
            r.summary += fmt::format(": digit {} set in {:.3g} of samples", res.worst_digit, res.worst_ones_fraction);
        r.summary += fmt::format("), combined p {:.3g}", p);
        r.verdict = Verdict::Pass;
        if (part.outside.count > 0) {
            r.verdict = Verdict::Fail;
            r.summary = fmt::format("{} remapped u outside [0,1)", part.outside.count);
            r.message = fmt::format("{} remapped u outside [0,1) (e.g. u = {} -> remapped {:.9g})", part.outside.count,
                                    format_input(part.outside.first->input, warp.input_kind()),
                                    part.outside.first->output[0]);
        }
        r.plots.push_back(remapped_histogram(part.u, warp.name()));
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_pmf_check() { return std::make_unique<PmfCheck>(); }
std::unique_ptr<Check> make_discrete_chi2_check() { return std::make_unique<DiscreteChi2Check>(); }
std::unique_ptr<Check> make_remapped_u_check() { return std::make_unique<RemappedUCheck>(); }

}  // namespace warpcheck
