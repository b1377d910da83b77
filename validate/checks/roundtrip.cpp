// Round trip: invert(sample(u)) must give u back.
//
// The rule, for uniform inputs (each part says why its tolerance has its size):
// - invert(x) must be a point of the input domain [0,1)^d; NaN or anything
//   outside fails, whatever sample then makes of it.
// - |invert(sample(u)) - u| (max norm) within the case's tolerance passes
//   (WarpCaseInfo::roundtrip_tolerance: float trigonometry loses tens of ulps).
// - 1D: a larger error that the output's own float resolution explains passes
//   and is counted as resolution-limited: sample(back) within 2 ulps of x, and
//   |back - u| within the u-measure of those 4 ulps, 4 pdf(x) spacing(x) (many
//   u share one float x where the warp squeezes them together).
// - Another preimage (sample(back) within the tolerance of x, back far from u)
//   is accepted only as a set of measure zero: a warp is not injective only on
//   poles, centres and seams, lines u_k = c that a random input hits with
//   probability at most 2^-24 each (the largest float spacing of [0,1)). Such a
//   line joins the two preimages, so every point of the segment from u to back
//   must map within the tolerance of x too (probed at 1/5 .. 4/5), and the
//   random inputs accepted that way may number at most the 1e-9 upper quantile
//   of a Poisson count with mean N 2^-24 * 8 (eight such lines); edge inputs,
//   which sit on such lines by construction, are counted and reported apart.
// Raw-bit inputs: the inverse must be exact: invert(x) fits the input's width,
// sample(invert(x)) == x, and invert(x) is the first preimage, so
// invert(x) <= the bits that produced x.
//
// The check is three parts: compute (one pass over the input chunks, counting),
// judge (the rule above, on the counts) and evidence (the worst inputs and the
// error histogram).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "chi2/count_bounds.h"
#include "sampling/float_bits.h"
#include "validate/checks/checks.h"
#include "validate/checks/evidence.h"
#include "validate/checks/formatting.h"
#include "validate/checks/input_chunks.h"

namespace warpcheck {
namespace {

constexpr std::size_t kWorstKept = 10;
constexpr int kFirstDecade = -10;  // error histogram: decades 1e-10 .. 1e0
constexpr int kDecades = 11;
constexpr double kLineProbability = 0x1p-24;  // largest chance of one input coordinate taking one value
constexpr double kSeamLines = 8.0;            // lines u_k = c where a warp may fail to be injective
constexpr double kBoundTail = 1e-9;           // chance that a correct warp exceeds the count bound

/// How one input's trip ended.
enum class Outcome {
    Within,         ///< |back - u| within the tolerance (or an exact first preimage for bits)
    Resolution,     ///< 1D: a larger error that x's float resolution explains
    OtherPreimage,  ///< sample(back) ~ x with back far from u: accepted on a set of measure zero
    OutsideInputs,  ///< back is NaN or outside the input domain
    Failed,         ///< back is a valid input that does not map to x
};

/// One input's trip: u -> x -> back.
struct Trip {
    double error = 0.0;  ///< |back - u| (max norm); for raw bits, how far below u the first preimage lies
    Outcome outcome = Outcome::Within;
    WarpInput input;
    WarpOutput output{};
    WarpInput back;

    bool failed() const { return outcome == Outcome::OutsideInputs || outcome == Outcome::Failed; }
};

/// What the compute part counts.
struct Stats {
    uint64_t count = 0, random_count = 0;
    uint64_t failures = 0, outside_inputs = 0;
    uint64_t other_edges = 0, other_random = 0;  ///< other preimages among edge and random inputs
    uint64_t resolution = 0;
    uint64_t exact = 0;
    // Over inputs that came back within the tolerance or failed; NaN wins. Edge
    // inputs apart: they sit on poles and seams, where an error up to the
    // tolerance is another preimage rather than imprecision.
    double max_error = 0.0, max_edge_error = 0.0;
    double max_resolution_error = 0.0;  // over resolution-limited inputs
    std::array<uint64_t, kDecades + 2> histogram{};  // [0]: below 1e-10 (not exact), [1..11]: decades, [12]: >= 10
    WorstK<Trip> worst{kWorstKept};                   // failures first (key inf), then largest errors

    void merge(const Stats& o) {
        count += o.count;
        random_count += o.random_count;
        failures += o.failures;
        outside_inputs += o.outside_inputs;
        other_edges += o.other_edges;
        other_random += o.other_random;
        resolution += o.resolution;
        exact += o.exact;
        max_error = max_nan_wins(max_error, o.max_error);
        max_edge_error = max_nan_wins(max_edge_error, o.max_edge_error);
        max_resolution_error = max_nan_wins(max_resolution_error, o.max_resolution_error);
        for (std::size_t k = 0; k < histogram.size(); ++k) histogram[k] += o.histogram[k];
        worst.merge(o.worst);
    }
};

/// The case's view of the rule: what is compared, with which tolerance.
struct Rule {
    InputKind kind = InputKind::Uniform1D;
    int in_dims = 1;
    int out_dims = 1;
    double tolerance = 0.0;  ///< the case's roundtrip_tolerance; unused (exact) for raw bits

    bool bits() const { return takes_bits(kind); }
    bool one_dimensional() const { return in_dims == 1 && out_dims == 1 && !bits(); }
};

double max_abs_diff(const WarpOutput& a, const WarpOutput& b, int dims) {
    double d = 0.0;
    for (int k = 0; k < dims; ++k)
        d = max_nan_wins(d, std::abs(static_cast<double>(a[k]) - static_cast<double>(b[k])));
    return d;
}

bool in_input_domain(const WarpInput& back, const Rule& rule) {
    if (rule.kind == InputKind::Bits32) return back.bits <= 0xffffffffu;
    if (rule.bits()) return true;
    for (int k = 0; k < rule.in_dims; ++k)
        if (!(back.u[k] >= 0.0f && back.u[k] < 1.0f)) return false;
    return true;
}

/// The spacing of floats at x: the width of the float that holds x.
double float_spacing(float x) {
    const float a = std::abs(x);
    return static_cast<double>(next_float_up(a)) - static_cast<double>(a);
}

Outcome bits_outcome(Trip& t, const WarpOutput& x2, const Rule& rule) {
    t.error = static_cast<double>(t.input.bits - std::min(t.input.bits, t.back.bits));
    const bool same = max_abs_diff(x2, t.output, rule.out_dims) == 0.0;
    return same && t.back.bits <= t.input.bits ? Outcome::Within : Outcome::Failed;
}

/// Judges one trip by the rule at the top of this file.
Trip judge_trip(const Rule& rule, const WarpInput& in, const WarpOutput& x, const WarpInput& back,
                const WarpOutput& x2, double pdf) {
    Trip t{0.0, Outcome::Within, in, x, back};
    if (!in_input_domain(back, rule)) {
        t.error = rule.bits() ? static_cast<double>(back.bits) : 0.0;
        if (!rule.bits())
            for (int k = 0; k < rule.in_dims; ++k)
                t.error = max_nan_wins(t.error, std::abs(static_cast<double>(back.u[k]) - in.u[k]));
        t.outcome = Outcome::OutsideInputs;
        return t;
    }
    if (rule.bits()) {
        t.outcome = bits_outcome(t, x2, rule);
        return t;
    }
    for (int k = 0; k < rule.in_dims; ++k)
        t.error = max_nan_wins(t.error, std::abs(static_cast<double>(back.u[k]) - in.u[k]));
    if (t.error <= rule.tolerance) return t;
    const double dx = max_abs_diff(x2, x, rule.out_dims);
    if (rule.one_dimensional()) {
        const double spacing = float_spacing(x[0]);
        if (dx <= 2.0 * spacing && t.error <= 4.0 * pdf * spacing) {
            t.outcome = Outcome::Resolution;
            return t;
        }
    }
    t.outcome = dx <= rule.tolerance ? Outcome::OtherPreimage : Outcome::Failed;
    return t;
}

void count_error(Stats& s, const Rule& rule, double error) {
    if (rule.bits()) return;
    if (error == 0.0) {
        ++s.exact;
    } else if (std::isfinite(error)) {
        const int decade = static_cast<int>(std::floor(std::log10(error)));
        s.histogram[static_cast<std::size_t>(std::clamp(decade - kFirstDecade + 1, 0, kDecades + 1))]++;
    }
}

void count_trip(Stats& s, const Rule& rule, Trip trip, bool edge, uint64_t index) {
    ++s.count;
    s.random_count += !edge;
    switch (trip.outcome) {
        case Outcome::OtherPreimage: ++(edge ? s.other_edges : s.other_random); return;
        case Outcome::Resolution:
            ++s.resolution;
            s.max_resolution_error = max_nan_wins(s.max_resolution_error, trip.error);
            return;
        case Outcome::OutsideInputs: ++s.outside_inputs; [[fallthrough]];
        case Outcome::Failed: ++s.failures; break;
        case Outcome::Within: break;
    }
    count_error(s, rule, trip.error);
    double& max = edge ? s.max_edge_error : s.max_error;
    max = max_nan_wins(max, trip.error);
    const double key = trip.failed() ? std::numeric_limits<double>::infinity() : trip.error;
    if (s.worst.wants(key)) s.worst.offer(key, index, std::move(trip));
}

/// Whether the segment from the input to the other preimage maps onto x: the
/// points 1/5 .. 4/5 of the way all land within the tolerance of x.
bool segment_maps_to_x(const WarpCase& warp, const Rule& rule, const Trip& t) {
    std::array<WarpInput, 4> probes{};
    for (std::size_t j = 0; j < probes.size(); ++j) {
        const float s = static_cast<float>(j + 1) / 5.0f;
        for (int k = 0; k < rule.in_dims; ++k) probes[j].u[k] = t.input.u[k] + s * (t.back.u[k] - t.input.u[k]);
    }
    std::array<WarpOutput, 4> out{};
    warp.sample(probes, out);
    for (const WarpOutput& o : out)
        if (!(max_abs_diff(o, t.output, rule.out_dims) <= rule.tolerance)) return false;
    return true;
}

Stats compute(const WarpCase& warp, const CheckContext& ctx, const Rule& rule) {
    auto parts = map_input_chunks<Stats>(ctx, warp.input_kind(), ctx.options().samples, true,
                                         [&](std::size_t chunk, std::span<const WarpInput> inputs) {
        Stats s;
        std::vector<WarpOutput> x(inputs.size()), x2(inputs.size());
        std::vector<WarpInput> back(inputs.size());
        std::vector<double> pdf(inputs.size(), 0.0);
        warp.sample(inputs, x);
        warp.invert(x, back);
        warp.sample(back, x2);
        if (rule.one_dimensional()) warp.pdf(x, pdf);
        const uint64_t base = chunk * kInputChunkSize;  // edge inputs first, then the random stream
        for (std::size_t i = 0; i < inputs.size(); ++i) {
            Trip trip = judge_trip(rule, inputs[i], x[i], back[i], x2[i], pdf[i]);
            if (trip.outcome == Outcome::OtherPreimage && !segment_maps_to_x(warp, rule, trip))
                trip.outcome = Outcome::Failed;
            count_trip(s, rule, std::move(trip), chunk == 0, base + i);
        }
        return s;
    });
    return merge_in_order(parts);
}

/// How many random inputs may come back as another preimage (see the top).
uint64_t other_preimage_bound(const Stats& s) {
    return chi2::poisson_count_bound(static_cast<double>(s.random_count) * kLineProbability * kSeamLines, kBoundTail);
}

std::vector<std::string> reasons(const Stats& s, const Rule& rule) {
    std::vector<std::string> why;
    const Trip* w = s.worst.empty() ? nullptr : &s.worst.front().item;
    auto example = [&] {
        return fmt::format("e.g. {} = {} -> x = {} -> invert {}", rule.bits() ? "bits" : "u",
                           format_input(w->input, rule.kind), format_output(w->output, rule.out_dims),
                           format_input(w->back, rule.kind));
    };
    if (s.outside_inputs > 0)
        why.push_back(fmt::format("{} of {} inputs: invert(x) is NaN or outside the input domain{}", s.outside_inputs,
                                  s.count, rule.bits() ? " (wider than the input)" : " [0,1)"));
    if (s.failures > s.outside_inputs)
        why.push_back(rule.bits() ? fmt::format("{} of {} inputs: sample(invert(x)) != x or invert(x) is not the first "
                                                "preimage",
                                                s.failures - s.outside_inputs, s.count)
                                  : fmt::format("{} of {} inputs come back further than {:.3g} from u",
                                                s.failures - s.outside_inputs, s.count, rule.tolerance));
    if (!why.empty() && w) why.back() += "; " + example();
    const uint64_t bound = other_preimage_bound(s);
    if (s.other_random > bound)
        why.push_back(fmt::format("{} of {} random inputs come back as another preimage of x, more than the {} a "
                                  "non-injective set of measure zero explains: the inverse is wrong on a set of "
                                  "positive measure",
                                  s.other_random, s.random_count, bound));
    return why;
}

/// The verdict: no input fails and the other preimages stay within the bound
/// for a set of measure zero.
void judge(CheckResult& r, const Stats& s, const Rule& rule) {
    const std::vector<std::string> why = reasons(s, rule);
    r.verdict = why.empty() ? Verdict::Pass : Verdict::Fail;
    r.message = join_reasons(why);
    if (rule.bits()) {
        r.summary = s.failures == 0 ? "exact inverse" : fmt::format("{} inputs not inverted", s.failures);
        return;
    }
    r.summary = fmt::format("max |du| {:.2e}", max_nan_wins(s.max_error, s.failures ? s.max_edge_error : 0.0));
    if (s.other_edges + s.other_random > 0) r.summary += fmt::format(", {} degenerate", s.other_edges + s.other_random);
    if (s.resolution > 0) r.summary += fmt::format(", {} resolution-limited", s.resolution);
}

void add_figures(CheckResult& r, const Stats& s, const Rule& rule) {
    r.samples = s.count;
    r.figures = {{"max_error", s.max_error},
                 {"max_edge_error", s.max_edge_error},
                 {"tolerance", rule.bits() ? 0.0 : rule.tolerance},
                 {"failures", static_cast<double>(s.failures)},
                 {"outside_input_domain", static_cast<double>(s.outside_inputs)},
                 {"degenerate", static_cast<double>(s.other_edges + s.other_random)},
                 {"other_preimage_edge_inputs", static_cast<double>(s.other_edges)},
                 {"other_preimage_random_inputs", static_cast<double>(s.other_random)},
                 {"other_preimage_bound", static_cast<double>(other_preimage_bound(s))},
                 {"other_preimage_fraction",
                  s.random_count ? static_cast<double>(s.other_random) / static_cast<double>(s.random_count) : 0.0},
                 {"resolution_limited", static_cast<double>(s.resolution)},
                 {"max_resolution_limited_error", s.max_resolution_error},
                 {"exact", static_cast<double>(s.exact)},
                 {"inputs", static_cast<double>(s.count)}};
}

void add_evidence(CheckResult& r, const Stats& s, const Rule& rule) {
    Table worst{"Worst inputs", {"input u", "sample(u)", "invert(sample(u))", rule.bits() ? "input offset" : "|du|"}, {}};
    for (const auto& e : s.worst.entries())
        worst.rows.push_back({format_input(e.item.input, rule.kind), format_output(e.item.output, rule.out_dims),
                              format_input(e.item.back, rule.kind),
                              e.item.failed() ? std::string("FAILED") : fmt::format("{:.3e}", e.item.error)});
    r.tables.push_back(std::move(worst));
    if (rule.bits()) return;

    Plot p;
    p.kind = Plot::Kind::Bars;
    p.title = fmt::format("Round-trip error per input (tolerance {:.2e}; {} exact, {} degenerate, {} resolution-limited)",
                          rule.tolerance, s.exact, s.other_edges + s.other_random, s.resolution);
    p.x_label = "log10 |invert(sample(u)) - u|";
    p.y_label = "inputs";
    p.log_y = true;
    Series bars{"inputs", {}, {}};
    for (int k = 0; k < kDecades + 2; ++k) {
        bars.x.push_back(kFirstDecade - 1 + k);
        bars.y.push_back(static_cast<double>(s.histogram[static_cast<std::size_t>(k)]));
    }
    p.series.push_back(std::move(bars));
    r.plots.push_back(std::move(p));
}

class RoundtripCheck final : public Check {
public:
    std::string name() const override { return "roundtrip"; }
    std::string description() const override {
        return "invert(sample(u)) == u over a seeded stream plus edge inputs (exact for raw-bit inputs)";
    }
    bool applies_to(const WarpCase& warp) const override { return warp.has_inverse(); }
    std::string not_applicable_because(const WarpCase& warp) const override {
        return warp.has_inverse() ? "" : "the warp has no inverse";
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const InputKind kind = warp.input_kind();
        const Rule rule{kind, input_dimension(kind), warp.domain().point_dimension(),
                        warp.info().roundtrip_tolerance};
        const Stats stats = compute(warp, ctx, rule);
        CheckResult r;
        judge(r, stats, rule);
        add_figures(r, stats, rule);
        add_evidence(r, stats, rule);
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_roundtrip_check() { return std::make_unique<RoundtripCheck>(); }

}  // namespace warpcheck
