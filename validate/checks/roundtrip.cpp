// Round trip: invert(sample(u)) must give u back.
//
// Uniform inputs: the error is max_k |invert(sample(u))_k - u_k|, compared with
// the case's tolerance. Where the warp is not injective (the azimuth at a pole,
// the centre of a disk) any preimage is as good as u; so when the input-space
// error is large, the output-space error |sample(invert(x)) - x| decides, and
// such points are counted as degenerate instead of failing.
// Raw-bit inputs: the inverse must be exact: sample(invert(x)) == x, and
// invert(x) is the first preimage, so invert(x) <= the bits that produced x.
//
// The check is three parts: compute (one pass over the input chunks, counting),
// judge (the rule above, on the counts) and evidence (the worst inputs and the
// error histogram).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "validate/checks/checks.h"
#include "validate/checks/evidence.h"
#include "validate/checks/formatting.h"
#include "validate/checks/input_chunks.h"

namespace warpcheck {
namespace {

constexpr std::size_t kWorstKept = 10;
constexpr int kFirstDecade = -10;  // error histogram: decades 1e-10 .. 1e0
constexpr int kDecades = 11;

/// One input's trip: u -> x -> back.
struct Trip {
    double error = 0.0;  ///< |back - u| (max norm); for raw bits, how far below u the first preimage lies
    bool failed = false;
    WarpInput input;
    WarpOutput output{};
    WarpInput back;
};

/// What the compute part counts.
struct Stats {
    uint64_t count = 0;
    uint64_t failures = 0;
    uint64_t degenerate = 0;
    uint64_t exact = 0;
    double max_error = 0.0;  // over non-degenerate points; NaN wins
    std::array<uint64_t, kDecades + 2> histogram{};  // [0]: below 1e-10 (not exact), [1..11]: decades, [12]: >= 10
    WorstK<Trip> worst{kWorstKept};                   // failures first (key inf), then largest errors

    void merge(const Stats& o) {
        count += o.count;
        failures += o.failures;
        degenerate += o.degenerate;
        exact += o.exact;
        max_error = max_nan_wins(max_error, o.max_error);
        for (std::size_t k = 0; k < histogram.size(); ++k) histogram[k] += o.histogram[k];
        worst.merge(o.worst);
    }
};

/// The case's view of the rule: what is compared, with which tolerance.
struct Rule {
    bool bits = false;
    int in_dims = 1;
    int out_dims = 1;
    double tolerance = 0.0;  ///< the case's roundtrip_tolerance; unused (exact) for raw bits
};

double max_abs_diff(const WarpOutput& a, const WarpOutput& b, int dims) {
    double d = 0.0;
    for (int k = 0; k < dims; ++k)
        d = max_nan_wins(d, std::abs(static_cast<double>(a[k]) - static_cast<double>(b[k])));
    return d;
}

/// Judges one trip: an exact first preimage for raw bits, the tolerance in u
/// (or, where another preimage came back, in x) for uniform inputs.
Trip judge_trip(const Rule& rule, const WarpInput& in, const WarpOutput& x, const WarpInput& back,
                const WarpOutput& x2, bool& degenerate) {
    Trip t{0.0, false, in, x, back};
    degenerate = false;
    if (rule.bits) {
        const bool same = max_abs_diff(x2, x, rule.out_dims) == 0.0;
        const bool first = back.bits <= in.bits;
        t.error = static_cast<double>(in.bits - std::min(in.bits, back.bits));
        t.failed = !(same && first);
        return t;
    }
    for (int k = 0; k < rule.in_dims; ++k)
        t.error = max_nan_wins(t.error, std::abs(static_cast<double>(back.u[k]) - in.u[k]));
    t.failed = !(t.error <= rule.tolerance);
    if (t.failed && max_abs_diff(x2, x, rule.out_dims) <= rule.tolerance) {
        t.failed = false;
        degenerate = true;
    }
    return t;
}

void count_trip(Stats& s, const Rule& rule, Trip trip, bool degenerate, uint64_t index) {
    ++s.count;
    if (degenerate) {
        ++s.degenerate;
        return;
    }
    if (trip.failed) ++s.failures;
    if (!rule.bits) {
        if (trip.error == 0.0) {
            ++s.exact;
        } else if (std::isfinite(trip.error)) {
            const int decade = static_cast<int>(std::floor(std::log10(trip.error)));
            s.histogram[static_cast<std::size_t>(std::clamp(decade - kFirstDecade + 1, 0, kDecades + 1))]++;
        }
    }
    s.max_error = max_nan_wins(s.max_error, trip.error);
    const double key = trip.failed ? std::numeric_limits<double>::infinity() : trip.error;
    if (s.worst.wants(key)) s.worst.offer(key, index, std::move(trip));
}

Stats compute(const WarpCase& warp, const CheckContext& ctx, const Rule& rule) {
    auto parts = map_input_chunks<Stats>(ctx, warp.input_kind(), ctx.options().samples, true,
                                         [&](std::size_t chunk, std::span<const WarpInput> inputs) {
        Stats s;
        std::vector<WarpOutput> x(inputs.size()), x2(inputs.size());
        std::vector<WarpInput> back(inputs.size());
        warp.sample(inputs, x);
        warp.invert(x, back);
        warp.sample(back, x2);
        const uint64_t base = chunk * kInputChunkSize;  // edge inputs first, then the random stream
        for (std::size_t i = 0; i < inputs.size(); ++i) {
            bool degenerate = false;
            Trip trip = judge_trip(rule, inputs[i], x[i], back[i], x2[i], degenerate);
            count_trip(s, rule, std::move(trip), degenerate, base + i);
        }
        return s;
    });
    return merge_in_order(parts);
}

/// The verdict: every input inverts (exactly for raw bits, within the case's
/// tolerance otherwise, which WarpCaseInfo::roundtrip_tolerance justifies).
void judge(CheckResult& r, const Stats& s, const Rule& rule, InputKind kind) {
    r.verdict = s.failures == 0 ? Verdict::Pass : Verdict::Fail;
    if (rule.bits) {
        r.summary = s.failures == 0 ? "exact inverse" : fmt::format("{} inputs not inverted", s.failures);
    } else {
        r.summary = fmt::format("max |du| {:.2e}", s.max_error);
        if (s.degenerate > 0) r.summary += fmt::format(", {} degenerate", s.degenerate);
    }
    if (s.failures == 0) return;
    const Trip& w = s.worst.front().item;
    const std::string example = fmt::format("{} -> x = {} -> invert {}", format_input(w.input, kind),
                                            format_output(w.output, rule.out_dims), format_input(w.back, kind));
    r.message = rule.bits ? fmt::format("{} of {} inputs: sample(invert(x)) != x or invert(x) is not the first "
                                        "preimage; e.g. bits {}",
                                        s.failures, s.count, example)
                          : fmt::format("{} of {} inputs come back further than {:.3g} from u; e.g. u = {}",
                                        s.failures, s.count, rule.tolerance, example);
}

void add_evidence(CheckResult& r, const Stats& s, const Rule& rule, InputKind kind) {
    r.samples = s.count;
    r.figures = {{"max_error", s.max_error},
                 {"tolerance", rule.bits ? 0.0 : rule.tolerance},
                 {"failures", static_cast<double>(s.failures)},
                 {"degenerate", static_cast<double>(s.degenerate)},
                 {"exact", static_cast<double>(s.exact)},
                 {"inputs", static_cast<double>(s.count)}};

    Table worst{"Worst inputs", {"input u", "sample(u)", "invert(sample(u))", rule.bits ? "input offset" : "|du|"}, {}};
    for (const auto& e : s.worst.entries())
        worst.rows.push_back({format_input(e.item.input, kind), format_output(e.item.output, rule.out_dims),
                              format_input(e.item.back, kind),
                              e.item.failed ? std::string("FAILED") : fmt::format("{:.3e}", e.item.error)});
    r.tables.push_back(std::move(worst));
    if (rule.bits) return;

    Plot p;
    p.kind = Plot::Kind::Bars;
    p.title = fmt::format("Round-trip error per input (tolerance {:.2e}; {} exact, {} degenerate)", rule.tolerance,
                          s.exact, s.degenerate);
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
    bool applies_to(const WarpCase&) const override { return true; }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const InputKind kind = warp.input_kind();
        const Rule rule{takes_bits(kind), input_dimension(kind), warp.domain().point_dimension(),
                        warp.info().roundtrip_tolerance};
        const Stats stats = compute(warp, ctx, rule);
        CheckResult r;
        judge(r, stats, rule, kind);
        add_evidence(r, stats, rule, kind);
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_roundtrip_check() { return std::make_unique<RoundtripCheck>(); }

}  // namespace warpcheck
