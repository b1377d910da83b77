// Exhaustive float histogram: every input of a float sampler's grid (all 2^32
// values for 32-bit samplers, every t = k 2^-24 for the lerps), each output
// float counted exactly and compared with the uniform measure of [a,b)
// (validate/api/exhaustive_sweep.h).
//
// Verdict, stated in the message when it fails:
// - FAIL if any output lies outside the half-open [a,b) (1.0 from [0,1), b
//   from a lerp), NaN included;
// - FAIL if a sampler that claims to be monotone in its input steps down;
// - FAIL if the outputs' reach [lowest, highest] leaves more ideal mass
//   outside it than a sampler of its grid must reach: one input's
//   (1 / inputs) for a sampler that claims monotonicity (issue 12); for one
//   that does not (a hash), the mass that `inputs` independent draws from the
//   ideal distribution leave unreached with probability 1e-9 (issue 22);
// - FAIL if --max-float-bias R is set and some float's count is off its
//   ideal by more than a factor R (bias_factor; issue 12);
// - otherwise PASS, with the bias as figures (and the most biased floats in
//   a table): distinct outputs, floats never
//   produced, per-binade min/max multiplicity against the ideal, the
//   alternation pattern, the total variation distance. A float sampler fed
//   with 32 bits cannot reach the 2^-149 spacing of [0,1), so every one of
//   them is biased somewhere; the question a rendering engineer asks is
//   whether it leaves the interval or breaks monotonicity (stratification,
//   inversion), and how large the bias is, which the figures answer exactly.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <boost/math/special_functions/gamma.hpp>
#include <fmt/format.h>

#include "reports/text.h"
#include "sampling/float_bits.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/evidence.h"
#include "validate/api/exhaustive_sweep.h"

namespace warpcheck {
namespace {

// The sweep of a Bits32 case that does not offer a fast block function: the
// batch interface, 2^32 times (slow, but exact).
FloatBlockFn generic_bits32_fn(const WarpCase& warp) {
    return [&warp](uint64_t first, std::size_t n, float* out) {
        thread_local std::vector<WarpInput> in;
        thread_local std::vector<WarpOutput> x;
        in.resize(n);
        x.resize(n);
        for (std::size_t i = 0; i < n; ++i) in[i] = WarpInput{{0.0f, 0.0f}, first + i};
        warp.sample(in, x);
        for (std::size_t i = 0; i < n; ++i) out[i] = x[i][0];
    };
}

std::string binade_label(const BinadeCount& b) {
    if (b.exponent == -127) return b.sign > 0 ? "denormals" : "-denormals";
    return fmt::format("{}[2^{}, 2^{})", b.sign > 0 ? "" : "-", b.exponent, b.exponent + 1);
}

// ---- evidence: multiplicity per binade (plot), every binade and the outside
// outputs (tables) ----
void add_evidence(CheckResult& r, const SweepSummary& s, const std::string& grid) {
    Plot p;
    p.kind = Plot::Kind::Lines;
    p.title = "Multiplicity per binade (" + grid + ")";
    p.x_label = "binade exponent e: [2^e, 2^(e+1)), -127 the denormals (positive side; the table has both)";
    p.y_label = "inputs per float";
    p.log_y = true;
    Series mn{"min", {}, {}}, ideal{"ideal", {}, {}}, mx{"max", {}, {}};
    for (const BinadeCount& bc : s.binades) {
        if (bc.sign < 0) continue;  // the plot shows the positive side; the table has both
        const double x = bc.exponent;
        // log axis: a zero minimum is drawn at the bottom (NaN leaves a gap).
        mn.x.push_back(x);
        mn.y.push_back(bc.min_multiplicity > 0 ? static_cast<double>(bc.min_multiplicity) : std::nan(""));
        ideal.x.push_back(x);
        ideal.y.push_back(bc.ideal);
        mx.x.push_back(x);
        mx.y.push_back(bc.max_multiplicity > 0 ? static_cast<double>(bc.max_multiplicity) : std::nan(""));
    }
    p.series = {std::move(mn), std::move(ideal), std::move(mx)};
    if (!p.series[0].x.empty()) r.plots.push_back(std::move(p));

    Table t{"Per binade (highest first)",
            {"binade", "floats", "produced", "ideal", "min", "max", "first float", "pattern (even/odd)",
             "sum |m - ideal| / inputs"},
            {}};
    for (auto it = s.binades.rbegin(); it != s.binades.rend(); ++it) {
        const BinadeCount& bc = *it;
        if (bc.inputs == 0 && bc.ideal < 1e-3 && t.rows.size() > 40) continue;  // keep the table readable
        t.rows.push_back({binade_label(bc), std::to_string(bc.floats), std::to_string(bc.distinct),
                          fmt::format("{:.6g}", bc.ideal), std::to_string(bc.min_multiplicity),
                          std::to_string(bc.max_multiplicity), std::to_string(bc.edge_multiplicity),
                          bc.pattern().empty() ? std::string("-") : bc.pattern(),
                          fmt::format("{:.3g}", bc.abs_deviation / static_cast<double>(s.inputs))});
    }
    r.tables.push_back(std::move(t));
    if (!s.outside_values.empty()) {
        Table o{"Outputs outside [a, b)", {"value", "inputs"}, {}};
        for (const OutsideValue& v : s.outside_values)
            o.rows.push_back({fmt::format("{} ({:a})", v.value, v.value), std::to_string(v.inputs)});
        r.tables.push_back(std::move(o));
    }
}

// ---- judge ----

// What the judge needs besides the counts.
struct Sweep {
    uint64_t inputs = 0;
    bool claims_monotone = false;
    std::string grid;
    float a = 0.0f, b = 1.0f;
    double max_float_bias = 0.0;  // 0: bias is reported, not failed
};

struct BiasedFloat {
    float value = 0.0f;
    uint64_t count = 0;
    double ideal = 0.0;
};

// The bias factor of a float produced c times against its ideal m: the smallest
// R with (m - 1) / R <= c <= R (m + 1). One input of slack each way, because
// rounding the input grid to floats moves up to one input between neighbours
// (the 257/255 and 3/1 alternations around ideals 256 and 2), which no sampler
// of the grid can avoid; a float whose ideal is at most one input may be
// missed. NaN never passes a comparison with R.
double bias_factor(uint64_t c, double m) {
    const double over = static_cast<double>(c) / (m + 1.0);
    if (!(m > 1.0)) return over;
    const double under = c > 0 ? (m - 1.0) / static_cast<double>(c) : std::numeric_limits<double>::infinity();
    return std::max(over, under);
}

// The most biased produced floats: per binade its most and least produced
// floats and its first float (a power of two, which also takes part of the
// spacing below), worst first.
WorstK<BiasedFloat> biased_floats(const SweepSummary& s) {
    WorstK<BiasedFloat> worst(10);
    uint64_t index = 0;
    auto offer = [&](float x, uint64_t c, double m) {
        if (c > 0) worst.offer(bias_factor(c, m), index, BiasedFloat{x, c, m});
        ++index;
    };
    for (const BinadeCount& bc : s.binades) {
        offer(bc.most_produced, bc.most_multiplicity, bc.ideal);
        offer(bc.least_produced, bc.least_multiplicity, bc.ideal);
        const float power = bc.exponent == -127 ? 0.0f : std::ldexp(1.0f, bc.exponent);
        if (bc.sign > 0 && bc.first == power) offer(bc.first, bc.edge_multiplicity, bc.ideal);
    }
    return worst;
}

// Floats never produced although their ideal exceeds one input: bias factor
// infinite (the table lists produced floats only).
uint64_t unreached_above_one_input(const SweepSummary& s) {
    uint64_t n = 0;
    for (const BinadeCount& bc : s.binades)
        if (bc.ideal > 1.0) n += bc.floats - bc.distinct;
    return n;
}

// Ideal probability of [a,b) outside the reach [lowest, highest] (the
// rounded-down uniform measure: highest stands for [highest, next float up)).
double mass_outside_reach(const SweepSummary& s, float a, float b) {
    if (s.distinct_inside == 0) return 1.0;
    const double width = static_cast<double>(b) - a;
    const double below = static_cast<double>(s.lowest_inside) - a;
    const double above = static_cast<double>(b) - next_float_up(s.highest_inside);
    return (below + above) / width;
}

// The chance that a correct sampler that is not monotone fails the reach rule.
// Not seeded (the sweep enumerates every input), so the rule cannot be in the
// run's Sidak family: its level is stated instead, far below any run's.
constexpr double kReachTail = 1e-9;

// The ideal mass a sampler may leave outside its reach. Monotone: one input's,
// since a monotone sampler of the grid comes within one input of each end.
// Otherwise, modelled as `inputs` independent draws from the ideal
// distribution, the mass below the lowest draw and that above the highest are
// close to independent exponentials of rate `inputs` (exactly, the chance that
// no draw falls in a set of mass m is (1 - m)^inputs <= e^(-m inputs)), so
// their sum is Gamma(2, 1 / inputs), exceeded with probability kReachTail at
// Q^-1(2, 1e-9) = 23.94 inputs' worth.
double reach_allowance(uint64_t inputs, bool claims_monotone) {
    const double one_input = 1.0 / static_cast<double>(inputs);
    if (claims_monotone) return one_input;
    static const double inputs_worth = boost::math::gamma_q_inv(2.0, kReachTail);
    return inputs_worth * one_input;
}

// The largest relative deviation of a multiplicity from its ideal, over the
// binades whose ideal is at least one input per float.
double max_relative_deviation(const SweepSummary& s) {
    double max_rel = 0.0;
    for (const BinadeCount& bc : s.binades) {
        if (!(bc.ideal >= 1.0)) continue;
        const double lo = std::abs(static_cast<double>(bc.min_multiplicity) - bc.ideal) / bc.ideal;
        const double hi = std::abs(static_cast<double>(bc.max_multiplicity) - bc.ideal) / bc.ideal;
        max_rel = std::max({max_rel, lo, hi});
    }
    return max_rel;
}

void add_figures(CheckResult& r, const SweepSummary& s, float b, double max_rel) {
    r.figures = {{"inputs", static_cast<double>(s.inputs)},
                 {"distinct", static_cast<double>(s.distinct)},
                 {"distinct_inside", static_cast<double>(s.distinct_inside)},
                 {"outside_count", static_cast<double>(s.outside_distinct)},
                 {"outside_inputs", static_cast<double>(s.outside_inputs)},
                 {"floats_in_interval", static_cast<double>(s.floats_in_interval)},
                 {"never_produced", static_cast<double>(s.never_produced)},
                 {"non_monotone_steps", static_cast<double>(s.non_monotone_steps)},
                 {"tv_distance", s.tv_distance},
                 {"max_relative_deviation", max_rel}};
    r.figures.push_back({"inputs_to_b", static_cast<double>(s.outside_inputs_of(b))});
    // The top binades' extremes as figures; all of them in the table and plot.
    const std::size_t shown = std::min<std::size_t>(s.binades.size(), 8);
    for (std::size_t k = s.binades.size() - shown; k < s.binades.size(); ++k) {
        const BinadeCount& bc = s.binades[k];
        if (bc.sign < 0) continue;
        r.figures.push_back({fmt::format("binade_{}_min", bc.exponent), static_cast<double>(bc.min_multiplicity)});
        r.figures.push_back({fmt::format("binade_{}_max", bc.exponent), static_cast<double>(bc.max_multiplicity)});
    }
}

// Issue 12's figures: the most biased float, the unreached floats, the reach.
struct Findings {
    double max_bias = 0.0;  // over produced floats
    uint64_t unreached = 0;  // never produced although above one input: bias factor infinite
    double mass_outside = 0.0;
    double resolution = 0.0;  // one input's probability
    double allowance = 0.0;   // the mass the reach rule allows outside (reach_allowance)
};

Findings add_bias_and_reach(CheckResult& r, const SweepSummary& s, const Sweep& sw) {
    Findings f;
    const WorstK<BiasedFloat> worst = biased_floats(s);
    f.unreached = unreached_above_one_input(s);
    f.max_bias = worst.empty() ? 0.0 : worst.front().key;
    f.mass_outside = mass_outside_reach(s, sw.a, sw.b);
    // A sampler with N equally likely inputs cannot give a float less than 1/N,
    // so the measure it leaves unreached at its ends may be up to one input's 1/N.
    f.resolution = 1.0 / static_cast<double>(sw.inputs);
    f.allowance = reach_allowance(sw.inputs, sw.claims_monotone);
    r.figures.push_back({"max_float_bias", f.max_bias});
    if (!worst.empty()) {
        r.figures.push_back({"most_biased_float", worst.front().item.value});
        r.figures.push_back({"most_biased_count", static_cast<double>(worst.front().item.count)});
        r.figures.push_back({"most_biased_ideal", worst.front().item.ideal});
    }
    r.figures.push_back({"unreached_above_one_input", static_cast<double>(f.unreached)});
    r.figures.push_back({"lowest_output", s.lowest_inside});
    r.figures.push_back({"highest_output", s.highest_inside});
    r.figures.push_back({"mass_outside_reach", f.mass_outside});
    r.figures.push_back({"input_resolution", f.resolution});
    r.figures.push_back({"reach_allowance", f.allowance});
    return f;
}

void add_bias_table(CheckResult& r, const WorstK<BiasedFloat>& worst) {
    Table t{"Most biased floats (bias factor: smallest R with (ideal - 1) / R <= count <= R (ideal + 1))",
            {"float", "count", "ideal", "bias factor"},
            {}};
    for (const auto& e : worst.entries())
        t.rows.push_back({fmt::format("{} ({:a})", e.item.value, e.item.value), std::to_string(e.item.count),
                          fmt::format("{:.6g}", e.item.ideal), fmt::format("{:.4g}", e.key)});
    if (!t.rows.empty()) r.tables.push_back(std::move(t));
}

CheckResult judge(const SweepSummary& s, const Sweep& sw) {
    CheckResult r;
    r.samples = s.inputs;
    const double max_rel = max_relative_deviation(s);
    add_figures(r, s, sw.b, max_rel);
    const Findings f = add_bias_and_reach(r, s, sw);

    std::string outside_text;
    for (std::size_t k = 0; k < s.outside_values.size() && k < 3; ++k)
        outside_text += fmt::format("{}{} inputs -> {}", k ? ", " : "", s.outside_values[k].inputs,
                                    s.outside_values[k].value);
    r.summary = fmt::format("{} distinct", s.distinct);
    if (s.outside_inputs > 0) r.summary += ", " + outside_text;
    if (s.non_monotone_steps > 0) r.summary += fmt::format(", {} steps down", s.non_monotone_steps);
    r.summary += fmt::format(", TV {:.3g}", s.tv_distance);

    const bool outside = s.outside_inputs > 0;
    const bool steps = sw.claims_monotone && s.non_monotone_steps > 0;
    const bool short_reach = !(f.mass_outside <= f.allowance);
    const bool biased = sw.max_float_bias > 0.0 && (f.unreached > 0 || !(f.max_bias <= sw.max_float_bias));
    r.verdict = outside || steps || short_reach || biased ? Verdict::Fail : Verdict::Pass;
    if (r.verdict == Verdict::Fail) {
        std::vector<std::string> why;
        if (outside)
            why.push_back(fmt::format("{} of {} inputs give outputs outside [{}, {}) ({})", s.outside_inputs,
                                      s.inputs, sw.a, sw.b, outside_text));
        if (steps)
            why.push_back(fmt::format("{} steps down although the sampler is monotone in its input",
                                      s.non_monotone_steps));
        if (short_reach)
            why.push_back(
                sw.claims_monotone
                    ? fmt::format("outputs reach only [{}, {}]: ideal mass {:.3g} outside it, more than one input's "
                                  "{:.3g}",
                                  s.lowest_inside, s.highest_inside, f.mass_outside, f.resolution)
                    : fmt::format("outputs reach only [{}, {}]: ideal mass {:.3g} outside it, more than the {:.3g} "
                                  "({:.1f} inputs' worth) that {} independent draws leave unreached with probability "
                                  "{:.0e}",
                                  s.lowest_inside, s.highest_inside, f.mass_outside, f.allowance,
                                  f.allowance / f.resolution, sw.inputs, kReachTail));
        if (biased)
            why.push_back(fmt::format("floats biased by up to a factor {:.4g} (--max-float-bias {}); {} floats "
                                      "whose ideal exceeds one input never produced",
                                      f.max_bias, sw.max_float_bias, f.unreached));
        r.message = join_reasons(why) +
                    ". Rule: an output outside the half-open interval, a step down of a monotone sampler, or a "
                    "reach leaving more than one input's mass (a monotone sampler) or more than independent draws "
                    "leave with probability 1e-9 (any other) fails; bias inside the interval is reported, failed "
                    "only beyond --max-float-bias.";
    } else {
        r.message = fmt::format("{}; rule: outside [a,b), steps down of a monotone sampler or a short reach "
                                "fail, bias is reported (TV distance {:.3g}, max relative deviation {:.3g}, "
                                "largest float bias factor {:.4g})",
                                sw.grid, s.tv_distance, max_rel, f.max_bias);
    }
    return r;
}

/// The plot's x: the binade exponent e of [2^e, 2^(e+1)), -127 for denormals and 0.
double binade_of(double v) {
    const double a = std::abs(v);
    if (!(a >= 0x1p-126)) return -127.0;
    return std::floor(std::log2(a));
}

/// On the inputs-per-float plot: the most biased float and the first outputs
/// outside [a, b) (from the row's table of them), at their binades.
void mark_exhaustive_plots(CheckResult& r) {
    const auto value = r.figure("most_biased_float"), count = r.figure("most_biased_count");
    const double ideal = r.figure("most_biased_ideal").value_or(NAN);
    const std::string ideal_text = std::isfinite(ideal) ? fmt::format("{:.3g}", ideal) : format_number(ideal);
    for (Plot& plot : r.plots) {
        if (plot.kind != Plot::Kind::Lines) continue;
        if (value && count && *count > 0.0)
            plot.highlights.push_back({binade_of(*value), *count,
                                       fmt::format("most biased: {:.9g} \u00d7{} (ideal {})", *value,
                                                   format_number(*count), ideal_text)});
        for (const Table& t : r.tables) {
            if (!t.title.starts_with("Outputs outside")) continue;
            for (std::size_t i = 0; i < t.rows.size() && i < 3; ++i) {
                if (t.rows[i].size() < 2) continue;
                const double v = std::strtod(t.rows[i][0].c_str(), nullptr);
                const double inputs = std::strtod(t.rows[i][1].c_str(), nullptr);
                if (std::isfinite(v) && inputs > 0)
                    plot.highlights.push_back(
                        {binade_of(v), inputs, fmt::format("outside [a, b): {:.9g} \u00d7{}", v, t.rows[i][1])});
            }
        }
        plot.note = "Inputs per float, per binade: min, ideal and max. Ringed: the most biased float and any output "
                    "outside [a, b) (at its binade). Outside outputs, steps down of a monotone sampler and a short reach "
                    "fail; bias is reported.";
    }
}

class ExhaustiveCheck final : public Check {
public:
    std::string name() const override { return "exhaustive"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"outside_inputs", "inputs whose output is outside [a, b)", FigureRule::Zero},
                 {"mass_outside_reach", "ideal mass outside the outputs' reach", FigureRule::AtMost, "reach_allowance"},
                 {"non_monotone_steps", "steps down (fail if the sampler claims to be monotone)", FigureRule::Counted},
                 {"max_float_bias", "largest float bias factor (fails only beyond --max-float-bias)", FigureRule::Counted},
                 {"unreached_above_one_input", "floats never produced whose ideal exceeds one input", FigureRule::Counted}},
                .marks = mark_exhaustive_plots};
    }
    bool uses_seed() const override { return false; }  // every input, no random stream
    CheckLegend legend() const override {
        return {name(), "Every input: outputs outside [a, b), steps down of a monotone sampler and a reach leaving "
                "more mass out than one input's (monotone) or than independent draws leave at 1e-9 (hash) fail; the "
                "bias of single floats is reported.",
                ""};
    }
    std::string description() const override {
        return "every input of a float sampler (all 2^32 for 32 bits; t = k 2^-24 for lerps), exact counts per "
               "output float against the uniform measure";
    }
    Applicability applicability(const WarpCase& warp) const override {
        return Applicability::when(warp.domain().is<chi2::Interval>() &&
                                   (dynamic_cast<const SweepableCase*>(&warp) != nullptr ||
                                    warp.input_kind() == InputKind::Bits32));
    }

    double time_budget(const RunOptions& options) const override {
        // The budget is asked before any warp is known: the largest grid, 2^32.
        return sweep_time_budget(options, uint64_t{1} << 32);
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const auto* sweepable = dynamic_cast<const SweepableCase*>(&warp);
        const FloatBlockFn fn = sweepable ? sweepable->sweep_fn() : generic_bits32_fn(warp);
        Sweep sw;
        sw.inputs = sweepable ? sweepable->sweep_inputs() : uint64_t{1} << 32;
        sw.claims_monotone = sweepable ? sweepable->claims_monotone() : false;
        sw.grid = sweepable ? sweepable->sweep_grid() : "all 2^32 inputs";
        sw.a = static_cast<float>(warp.domain().a());
        sw.b = static_cast<float>(warp.domain().b());
        sw.max_float_bias = ctx.options().max_float_bias;
        const FloatBordersFn borders = sweepable ? sweepable->sweep_borders_fn() : FloatBordersFn{};
        const SweepSummary s = exhaustive_sweep(fn, borders, sw.inputs, sw.a, sw.b, ctx.executor());
        CheckResult r = judge(s, sw);
        add_evidence(r, s, sw.grid);
        add_bias_table(r, biased_floats(s));
        r.phases = {{"run counting", s.runs_seconds}};
        if (s.exact_fallback) r.phases.push_back({"non-monotone recount", s.recount_seconds});
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_exhaustive_check() { return std::make_unique<ExhaustiveCheck>(); }

}  // namespace warpcheck
