// Exhaustive float histogram: every input of a float sampler's grid (all 2^32
// values for 32-bit samplers, every t = k 2^-24 for the lerps), each output
// float counted exactly and compared with the uniform measure of [a,b)
// (validate/exhaustive_sweep.h).
//
// Verdict, stated in the message when it fails:
// - FAIL if any output lies outside the half-open [a,b) (1.0 from [0,1), b
//   from a lerp), NaN included;
// - FAIL if a sampler that claims to be monotone in its input steps down;
// - otherwise PASS, with the bias as figures: distinct outputs, floats never
//   produced, per-binade min/max multiplicity against the ideal, the
//   alternation pattern, the total variation distance. A float sampler fed
//   with 32 bits cannot reach the 2^-149 spacing of [0,1), so every one of
//   them is biased somewhere; the question a rendering engineer asks is
//   whether it leaves the interval or breaks monotonicity (stratification,
//   inversion), and how large the bias is, which the figures answer exactly.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "validate/checks/checks.h"
#include "validate/exhaustive_sweep.h"

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

class ExhaustiveCheck final : public Check {
public:
    std::string name() const override { return "exhaustive"; }
    bool uses_seed() const override { return false; }  // every input, no random stream
    std::string description() const override {
        return "every input of a float sampler (all 2^32 for 32 bits; t = k 2^-24 for lerps), exact counts per "
               "output float against the uniform measure";
    }
    bool applies_to(const WarpCase& warp) const override {
        if (!warp.domain().is<chi2::Interval>()) return false;
        return dynamic_cast<const SweepableCase*>(&warp) != nullptr || warp.input_kind() == InputKind::Bits32;
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const auto* sweepable = dynamic_cast<const SweepableCase*>(&warp);
        const FloatBlockFn fn = sweepable ? sweepable->sweep_fn() : generic_bits32_fn(warp);
        const uint64_t inputs = sweepable ? sweepable->sweep_inputs() : uint64_t{1} << 32;
        const bool claims_monotone = sweepable ? sweepable->claims_monotone() : false;
        const std::string grid = sweepable ? sweepable->sweep_grid() : "all 2^32 inputs";
        const auto a = static_cast<float>(warp.domain().a());
        const auto b = static_cast<float>(warp.domain().b());

        const SweepSummary s = exhaustive_sweep(fn, inputs, a, b, ctx.executor());

        CheckResult r;
        r.samples = s.inputs;
        // The largest relative deviation of a multiplicity from its ideal, over
        // the binades whose ideal is at least one input per float.
        double max_rel = 0.0;
        for (const BinadeCount& bc : s.binades) {
            if (!(bc.ideal >= 1.0)) continue;
            const double lo = std::abs(static_cast<double>(bc.min_multiplicity) - bc.ideal) / bc.ideal;
            const double hi = std::abs(static_cast<double>(bc.max_multiplicity) - bc.ideal) / bc.ideal;
            max_rel = std::max({max_rel, lo, hi});
        }
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

        std::string outside_text;
        for (std::size_t k = 0; k < s.outside_values.size() && k < 3; ++k)
            outside_text += fmt::format("{}{} inputs -> {}", k ? ", " : "", s.outside_values[k].inputs,
                                        s.outside_values[k].value);
        r.summary = fmt::format("{} distinct", s.distinct);
        if (s.outside_inputs > 0) r.summary += ", " + outside_text;
        if (s.non_monotone_steps > 0) r.summary += fmt::format(", {} steps down", s.non_monotone_steps);
        r.summary += fmt::format(", TV {:.3g}", s.tv_distance);

        const bool outside = s.outside_inputs > 0;
        const bool steps = claims_monotone && s.non_monotone_steps > 0;
        r.verdict = outside || steps ? Verdict::Fail : Verdict::Pass;
        if (r.verdict == Verdict::Fail) {
            std::string why;
            if (outside)
                why = fmt::format("{} of {} inputs give outputs outside [{}, {}) ({})", s.outside_inputs, s.inputs, a,
                                  b, outside_text);
            if (steps)
                why += fmt::format("{}{} steps down although the sampler is monotone in its input", why.empty() ? "" : "; ",
                                   s.non_monotone_steps);
            r.message = why + ". Rule: an output outside the half-open interval, or a step down of a monotone "
                              "sampler, fails; bias inside the interval is reported, not failed.";
        } else {
            r.message = fmt::format("{}; rule: outside [a,b) or steps down of a monotone sampler fail, bias is "
                                    "reported (TV distance {:.3g}, max relative deviation {:.3g})",
                                    grid, s.tv_distance, max_rel);
        }

        add_evidence(r, s, grid);
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_exhaustive_check() { return std::make_unique<ExhaustiveCheck>(); }

}  // namespace warpcheck
