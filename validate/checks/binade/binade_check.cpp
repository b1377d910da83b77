// Binade mass and significand parity of 64-bit float samplers: the statistical
// view of what the exhaustive counts show for 32-bit ones.
//
// Cells: the binades of [a,b) (sign and exponent; a negative binade holds the
// magnitudes (2^e, 2^(e+1)], where the spacing is constant). Their probability
// under the uniform measure is exact: the length of the binade's reals within
// [a,b), over b - a. Binades expected to get fewer than 5 samples are pooled
// as chi2::pearson_test pools (no binade is ever dropped).
// Parity: within a binade every float has the same probability, so even and
// odd significands split its samples in proportion to their counts (1/2 for a
// full binade). A 257/255 alternation moves 1/512 of the mass from odd to even,
// which at 2^23 samples in [0.5,1) is 11 standard deviations: hence at least
// 2^24 samples, whatever --samples says below that.
// Resolution (issue 22, chi2/resolution_test.h): the binary digits of
// (x - a) / (b - a) down to 2^-20 must be fair coins. Tested where the halves
// of every digit are unions of whole floats, so that the exact sampler (every
// float with its spacing's probability) is exactly uniform in them: b - a a
// power of two, a a multiple of (b - a) 2^-20, and no float spacing of [a, b]
// wider than that ([0,1), [-3,5), [-1,-0.75) qualify; [0.001,1000) does not).
// A sampler that keeps 16 random bits fails it, whatever its binade masses.
// Both Pearson statistics come from the engine (chi2/pearson.h): no degrees of
// freedom gives a NaN p-value. A test without degrees of freedom (an interval
// inside one binade has no mass test) is left out of the combination and of
// the row; with none left the check tested nothing and is n/a. The check
// reports p = min(1, k min(p_i)) over its k tests (Bonferroni), which the
// runner compares with its Šidák-corrected level.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "chi2/multiple_testing.h"
#include "chi2/pearson.h"
#include "chi2/power.h"
#include "chi2/resolution_test.h"
#include "sampling/float_bits.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/input_chunks.h"
#include "validate/checks/shared/power_level.h"

namespace warpcheck {
namespace {

constexpr uint64_t kMinSamples = uint64_t{1} << 24;
constexpr double kMinParityExpected = 100.0;  // per parity, for a binade's parity term

// Binade of a float: +/-(exponent field + 1), 0 never used; for negative
// floats the exponent field of the next float towards zero.
int binade_key(float x) {
    const uint32_t bits = float_to_bits(x) & 0x7fffffffu;
    if (x >= 0.0f) return static_cast<int>(bits >> 23) + 1;
    return -(static_cast<int>((bits - 1) >> 23) + 1);
}

struct Cell {
    int key = 0;
    double probability = 0.0;
    double even_fraction = 0.5;
    uint64_t observed = 0, even = 0;
};

uint64_t evens_in(uint64_t p, uint64_t q) { return q < p ? 0 : (q >> 1) - ((p + 1) >> 1) + 1; }

// The cells of [a,b): every binade with some of the interval.
std::vector<Cell> cells_of(double a, double b) {
    std::vector<Cell> cells;
    const double width = b - a;
    for (int sign : {-1, 1}) {
        for (int field = 0; field < 255; ++field) {
            // Reals that round down into the binade: [lo, hi).
            const double lo_mag = field == 0 ? 0.0 : std::ldexp(1.0, field - 127);
            const double hi_mag = std::ldexp(1.0, field - 126);
            const double lo = sign > 0 ? lo_mag : -hi_mag, hi = sign > 0 ? hi_mag : -lo_mag;
            const double from = std::max(lo, a), to = std::min(hi, b);
            if (!(from < to)) continue;
            Cell c;
            c.key = sign * (field + 1);
            c.probability = (to - from) / width;
            // The floats of the cell, as bit patterns of their magnitudes.
            const float first = static_cast<float>(from);
            const float last = next_float_down(static_cast<float>(to));
            uint64_t p = float_to_bits(std::fabs(first)) & 0x7fffffffu;
            uint64_t q = float_to_bits(std::fabs(last)) & 0x7fffffffu;
            if (p > q) std::swap(p, q);
            c.even_fraction = static_cast<double>(evens_in(p, q)) / static_cast<double>(q - p + 1);
            cells.push_back(c);
        }
    }
    std::sort(cells.begin(), cells.end(), [](const Cell& x, const Cell& y) { return x.key < y.key; });
    return cells;
}

std::string cell_label(int key) {
    const int field = std::abs(key) - 1;
    const std::string sign = key < 0 ? "-" : "";
    if (field == 0) return sign + "denormals";
    return fmt::format("{}2^{}", sign, field - 127);
}

// ---- compute: counts per binade, a map-reduce over input chunks ----

// The digits of (x - a) / (b - a) tested for resolution (see the top), or 0.
int resolution_digits(double a, double b) {
    const double width = b - a;
    int exponent = 0;
    if (!(std::frexp(width, &exponent) == 0.5)) return 0;  // not a power of two
    const double grid = std::ldexp(width, -chi2::kResolutionDigits);
    const auto largest = static_cast<float>(std::max(std::abs(a), std::abs(b)));
    const double spacing = static_cast<double>(next_float_up(largest)) - static_cast<double>(largest);
    return std::fmod(a, grid) == 0.0 && spacing <= grid ? chi2::kResolutionDigits : 0;
}

struct Counts {
    std::vector<uint64_t> in, even;
    uint64_t outside = 0, nan = 0;  ///< outside [a, b) (NaN included), and NaN
    chi2::DigitCounts digits;
};

/// Samples that are not in [a, b), and how many of them are NaN.
struct Strays {
    uint64_t outside = 0, nan = 0;
};

// Adds every sample to its binade in `cells` and (where digits > 0) its digits
// to `digits`; returns the samples outside [a,b).
Strays count_binades(const WarpCase& warp, const CheckContext& ctx, uint64_t samples, std::vector<Cell>& cells,
                       chi2::DigitCounts& digits, bool test_digits) {
    const double a = warp.domain().a(), b = warp.domain().b();
    // The cell of each binade key (-256 .. 256, offset by kKeys), or -1: a
    // table, as every one of the 2^24 samples or more looks its key up.
    constexpr int kKeys = 256;
    std::array<int, 2 * kKeys + 1> index;
    index.fill(-1);
    for (std::size_t k = 0; k < cells.size(); ++k) index[static_cast<std::size_t>(cells[k].key + kKeys)] = static_cast<int>(k);
    auto chunks = map_input_chunks<Counts>(ctx, warp.input_kind(), samples, false, [&](std::size_t, auto inputs) {
        Counts c{std::vector<uint64_t>(cells.size(), 0), std::vector<uint64_t>(cells.size(), 0), 0, 0,
                 chi2::DigitCounts(digits.digits())};
        std::vector<WarpOutput> x(inputs.size());
        warp.sample(inputs, x);
        for (const WarpOutput& o : x) {
            const float v = o[0];
            const int cell = (v >= a && v < b) ? index[static_cast<std::size_t>(binade_key(v) + kKeys)] : -1;
            if (cell < 0) {
                ++c.outside;
                c.nan += std::isnan(v);
                continue;
            }
            const auto k = static_cast<std::size_t>(cell);
            ++c.in[k];
            c.even[k] += (float_to_bits(v) & 1u) == 0;
            // x - a is exact in double unless |x| < 2^-29 |a|, which can move x
            // across the grid line at 0 only from within 2^-53 |a| of it.
            if (test_digits) c.digits.add((static_cast<double>(v) - a) / (b - a));
        }
        return c;
    });
    Strays strays;
    for (const Counts& c : chunks) {  // chunk order: the sums do not depend on the threads
        strays.outside += c.outside;
        strays.nan += c.nan;
        digits.merge(c.digits);
        for (std::size_t k = 0; k < c.in.size(); ++k) {
            cells[k].observed += c.in[k];
            cells[k].even += c.even[k];
        }
    }
    return strays;
}

// ---- the two statistics ----

struct ParityTest {
    double statistic = 0.0;
    int cells = 0;
    double p_value = 0.0;
    double worst_term = 0.0;
    int worst_key = 0;
};

struct Tests {
    chi2::PearsonResult mass;
    ParityTest parity;
    chi2::ResolutionTest resolution;  ///< digits 0: not tested
    int tests = 0;         ///< how many of the three have something to test
    double p_value = 0.0;  ///< Bonferroni over those; NaN if any is NaN or none is left

    bool mass_tested() const { return mass.dof >= 1; }
    bool parity_tested() const { return parity.cells >= 1; }
    bool resolution_tested() const { return resolution.digits >= 1; }
};

chi2::PearsonResult test_mass(const std::vector<Cell>& cells, double n) {
    std::vector<double> observed, expected;
    for (const Cell& c : cells) {
        observed.push_back(static_cast<double>(c.observed));
        expected.push_back(c.probability * n);
    }
    return chi2::pearson_test(observed, expected, chi2::kMinExpectedCount);
}

// Within a binade the parity split is binomial given the binade's count: one
// degree of freedom per binade with enough of each parity expected.
ParityTest test_parity(const std::vector<Cell>& cells) {
    ParityTest t;
    for (const Cell& c : cells) {
        const double o = static_cast<double>(c.observed);
        const double e_even = o * c.even_fraction, e_odd = o - e_even;
        if (!(e_even >= kMinParityExpected && e_odd >= kMinParityExpected)) continue;
        const double d = static_cast<double>(c.even) - e_even;
        const double term = d * d / e_even + d * d / e_odd;
        t.statistic += term;
        ++t.cells;
        if (term > t.worst_term) {
            t.worst_term = term;
            t.worst_key = c.key;
        }
    }
    t.p_value = chi2::chi_square_upper_tail(t.statistic, t.cells);
    return t;
}

// Bonferroni over the tests that have something to test. A test without any
// (an interval inside one binade has a single mass term) is left out, visibly
// (its p-value stays NaN in the figures); with none left the combined p is NaN
// and the check reports that it tested nothing.
Tests test_binades(const std::vector<Cell>& cells, double n, const chi2::DigitCounts& digits, bool test_digits) {
    Tests t;
    t.mass = test_mass(cells, n);
    t.parity = test_parity(cells);
    if (test_digits) t.resolution = chi2::resolution_test(digits);
    std::vector<double> ps;
    if (t.mass_tested()) ps.push_back(t.mass.p_value);
    if (t.parity_tested()) ps.push_back(t.parity.p_value);
    if (t.resolution_tested()) ps.push_back(t.resolution.p_value);
    t.tests = static_cast<int>(ps.size());
    t.p_value = ps.empty() ? std::numeric_limits<double>::quiet_NaN() : 1.0;
    for (double p : ps) {
        if (std::isnan(p)) {  // a NaN test makes a NaN check: it fails
            t.p_value = p;
            break;
        }
        t.p_value = std::min(t.p_value, std::min(1.0, static_cast<double>(ps.size()) * p));
    }
    return t;
}

// ---- judge ----

// "binade mass 0.3, parity 0.7, resolution 0.5 (2^-20)": the tests that ran, no NaN.
std::string tests_text(const Tests& t) {
    std::vector<std::string> parts;
    if (t.mass_tested()) parts.push_back(fmt::format("binade mass {:.3g}", t.mass.p_value));
    if (t.parity_tested()) parts.push_back(fmt::format("parity {:.3g}", t.parity.p_value));
    if (t.resolution_tested())
        parts.push_back(fmt::format("resolution {:.3g} (2^-{})", t.resolution.p_value, t.resolution.digits));
    std::string text;
    for (const std::string& part : parts) text += (text.empty() ? "" : ", ") + part;
    if (!t.mass_tested()) text += "; one binade: no mass test";
    return text;
}

// Fail on any sample outside [a,b): no tolerance, a float sampler must stay in
// its interval exactly. Otherwise the runner compares p with its corrected level
// (a NaN p fails there); a check with nothing to test is n/a.
CheckResult judge(const Tests& t, const Strays& strays, uint64_t samples, double a, double b) {
    CheckResult r;
    r.samples = samples;
    r.figures = {{"samples", static_cast<double>(samples)},
                 {"mass_chi2", t.mass.statistic},
                 {"mass_dof", static_cast<double>(t.mass.dof)},
                 {"mass_p_value", t.mass.p_value},
                 {"parity_chi2", t.parity.statistic},
                 {"parity_dof", static_cast<double>(t.parity.cells)},
                 {"parity_p_value", t.parity.p_value},
                 {"resolution_digits", static_cast<double>(t.resolution.digits)},
                 {"resolution_p_value", t.resolution_tested() ? t.resolution.p_value : std::nan("")},
                 {"resolution_worst_digit", static_cast<double>(t.resolution.worst_digit)},
                 {"outside", static_cast<double>(strays.outside)},
                 {"nan_samples", static_cast<double>(strays.nan)}};
    if (strays.outside > 0) {
        r.verdict = Verdict::Fail;
        std::vector<std::string> why;
        if (strays.nan > 0) why.push_back(fmt::format("{} of {} samples are NaN", strays.nan, samples));
        if (strays.outside > strays.nan)
            why.push_back(
                fmt::format("{} of {} samples lie outside [{}, {})", strays.outside - strays.nan, samples, a, b));
        r.message = why.size() == 1 ? why[0] : why[0] + "; " + why[1];
        r.summary = r.message;
        return r;
    }
    if (t.tests == 0) {
        r.verdict = Verdict::NotApplicable;
        r.summary = "not applicable: the interval holds one binade and too few floats for the parity and "
                    "resolution tests";
        return r;
    }
    r.p_value = t.p_value;
    r.summary = fmt::format("p {:.3g} ({})", t.p_value, tests_text(t));
    r.verdict = Verdict::Pass;  // the runner applies the corrected level to p
    if (t.parity_tested() && t.parity.p_value < 1e-3)
        r.message = fmt::format("largest parity deviation in binade {}", cell_label(t.parity.worst_key));
    if (t.resolution_tested() && t.resolution.p_value < 1e-3)
        r.message += fmt::format("{}digit {} of (x - a) / (b - a) set in {:.4g} of the samples",
                                 r.message.empty() ? "" : "; ", t.resolution.worst_digit,
                                 t.resolution.worst_ones_fraction);
    return r;
}

// ---- stated power (chi2/power.h's noncentral chi-square) ----

// The deviations each test detects with 90% probability at its share of the
// planned level (Bonferroni over the tests that ran): for the mass test, a
// relative excess d of the largest binade's mass, the rest scaled down to keep
// the total (noncentrality N p d^2 / (1 - p)); for the parity test, a shift s
// of every tested binade's even share f (noncentrality sum_b n_b s^2 /
// (f (1 - f))); for the resolution test, a shift s of one digit's share of
// ones from 1/2 at its Sidak share of the test's level (noncentrality 4 N s^2).
// A test that did not run has no power (NaN in the figures, absent from the row).
void add_power(CheckResult& r, const Tests& t, const std::vector<Cell>& cells, double n, const RunOptions& options) {
    const double level = power_level(options, 1) / std::max(t.tests, 1);
    double largest = 0.0, parity_weight = 0.0;
    for (const Cell& c : cells) {
        largest = std::max(largest, c.probability);
        const double e_even = static_cast<double>(c.observed) * c.even_fraction;
        if (e_even >= kMinParityExpected && static_cast<double>(c.observed) - e_even >= kMinParityExpected)
            parity_weight += n * c.probability / (c.even_fraction * (1.0 - c.even_fraction));
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double mass = t.mass_tested() ? std::sqrt(chi2::pearson_noncentrality_for_power(t.mass.dof, level) *
                                                    (1.0 - largest) / (n * largest))
                                        : nan;
    const double parity =
        t.parity_tested() ? std::sqrt(chi2::pearson_noncentrality_for_power(t.parity.cells, level) / parity_weight)
                          : nan;
    const double digit_level = chi2::sidak_level(level, std::max(t.resolution.digits, 1));
    const double digit = t.resolution_tested()
                             ? std::sqrt(chi2::pearson_noncentrality_for_power(1.0, digit_level) / (4.0 * n))
                             : nan;
    r.figures.insert(r.figures.end(), {{"power_mass_relative_excess", mass},
                                       {"power_parity_shift", parity},
                                       {"power_digit_shift", digit},
                                       {"power_level", level}});
    if (r.verdict != Verdict::Pass) return;  // a failure's row names the failure, an n/a row why
    std::string text;
    if (t.mass_tested()) text += fmt::format("largest binade {:+.2g}", mass);
    if (t.parity_tested()) text += fmt::format("{}even share {:+.2g}", text.empty() ? "" : ", ", parity);
    if (t.resolution_tested()) text += fmt::format("{}a digit's share {:+.2g}", text.empty() ? "" : ", ", digit);
    if (!text.empty()) r.summary += "; 90% power: " + text;
}

// ---- evidence: a table of binades and a plot of observed / expected ----

void add_evidence(CheckResult& r, const std::vector<Cell>& cells, double n) {
    Table t{"Binades (largest first)", {"binade", "expected", "observed", "even share expected", "even observed"}, {}};
    Plot plot;
    plot.kind = Plot::Kind::Points;
    plot.title = "Samples per binade: observed / expected";
    plot.x_label = "binade (signed exponent index)";
    plot.y_label = "observed / expected";
    Series ratio{"observed / expected", {}, {}};
    for (auto it = cells.rbegin(); it != cells.rend(); ++it) {
        const double e = it->probability * n;
        if (e < 1e-3 && it->observed == 0) continue;
        const double observed = static_cast<double>(it->observed);
        t.rows.push_back({cell_label(it->key), fmt::format("{:.1f}", e), std::to_string(it->observed),
                          fmt::format("{:.6f}", it->even_fraction),
                          it->observed ? fmt::format("{:.6f}", static_cast<double>(it->even) / observed)
                                       : std::string("-")});
        if (e >= chi2::kMinExpectedCount) {
            ratio.x.push_back(it->key);
            ratio.y.push_back(observed / e);
        }
    }
    r.tables.push_back(std::move(t));
    plot.series.push_back(std::move(ratio));
    r.plots.push_back(std::move(plot));
}

class BinadeCheck final : public Check {
public:
    std::string name() const override { return "binade"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"outside", "samples outside [a, b)", FigureRule::Zero}},
                .p_values =
                    [](const CheckResult& r, double level, std::vector<JudgedQuantity>& out) {
                        shared_p_lines(r, level, out,
                                       {{"mass_p_value", "mass per binade: Pearson p-value"},
                                        {"parity_p_value", "significand parity: Pearson p-value"},
                                        {"resolution_p_value", "binary digits of (x \u2212 a) / (b \u2212 a): p-value"}});
                    },
                .p_value = "p-value: the smallest test's, times the number of tests, at most 1"};
    }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "Pearson's X\u00b2 of the mass per binade and of the significand parity within binades, and "
                "where the interval allows, of each binary digit of (x \u2212 a) / (b \u2212 a).",
                "min(1, k \u00d7 min p) over the k tests made (Bonferroni)."};
    }
    std::string description() const override {
        return "64-bit float samplers: chi-square of the mass per binade, of the significand parity within "
               "binades and of the binary digits down to 2^-20 (at least 2^24 samples)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        return Applicability::when(warp.input_kind() == InputKind::Bits64 && warp.domain().is<chi2::Interval>());
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const double a = warp.domain().a(), b = warp.domain().b();
        std::vector<Cell> cells = cells_of(a, b);
        const uint64_t samples = std::max(ctx.options().samples, kMinSamples);
        const bool test_digits = resolution_digits(a, b) > 0;
        chi2::DigitCounts digits;
        const Strays strays = count_binades(warp, ctx, samples, cells, digits, test_digits);
        const Tests tests = test_binades(cells, static_cast<double>(samples), digits, test_digits);
        CheckResult r = judge(tests, strays, samples, a, b);
        add_power(r, tests, cells, static_cast<double>(samples), ctx.options());
        add_evidence(r, cells, static_cast<double>(samples));
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_binade_check() { return std::make_unique<BinadeCheck>(); }

}  // namespace warpcheck
