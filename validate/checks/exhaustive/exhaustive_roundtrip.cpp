// Exhaustive round trip of 1D warps: every float u of [0,1) (1,065,353,216 of
// them, denormals included), not a sample of them.
//
// For each u: x = sample(u), u' = invert(x), p = pdf(x). Counted: round trips
// further than the case's tolerance from u (NaN counts), pdfs that are not
// finite and positive, and steps of sample in each direction between
// consecutive floats u. A pdf of 0 is legitimate only at an output exactly on
// the domain's boundary (chi2::Domain::on_boundary, the consistency check's
// rule): such outputs are counted and reported (boundary_zero_pdf), not failed.
// invert(x) must lie in [0,1), as in the sampled round trip (roundtrip.cpp):
// a value outside fails (outside_input_domain; NaN already fails the
// tolerance), except exactly 1.0 for u at the edge of 1 (u one of the two
// largest floats below 1, or 1 - u within 4 pdf(x) spacing(x), the u-measure
// of x's float cell): u rounded to 1, counted (rounded_to_one), passing by
// default and failing under --strict (RunOptions::strict), since renderers
// clamp u below 1 where they use it.
// Verdict: FAIL on any round-trip failure, on any invert(x) outside [0,1)
// but those, on any other pdf that is not finite
// and positive, or when sample steps back against its direction (the direction
// of the majority of its steps) by more than kWobbleUlps ulps (a 1D inversion
// warp is monotone; a real step back breaks stratification, while a rounding
// wobble of a few ulps is reported: steps_back, max_step_back_ulps).
//
// It goes through the warp's batch interface, ~1e9 calls: seconds per case on
// two cores, so it runs only with --exhaustive (runs_by_default).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "sampling/float_bits.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/float_cell.h"
#include "validate/checks/shared/formatting.h"
#include "validate/api/exhaustive_sweep.h"

namespace warpcheck {
namespace {

constexpr uint32_t kUnitFloats = 0x3f800000u;  // bit patterns of [0,1): 0 .. 0x3f7fffff
constexpr uint32_t kChunk = uint32_t{1} << 20;
constexpr std::size_t kBatch = 4096;
// The largest step back (in ulps of the output) that is rounding wobble, not a
// defect: a monotone formula evaluated in n correctly rounded operations, each
// off by at most half an ulp of a value no larger than its output, is within
// n/2 ulps of the exact monotone value at every input, so two consecutive
// outputs can step back by at most n ulps. Lerp-like 1D warps, a + t (b - a) or
// (1 - t) a + t b, round at most 4 times: 4 ulps. A defect such as a 6e-4 step
// near 1 is ~5000 ulps.
constexpr uint64_t kWobbleUlps = 4;
// u rounded to 1 (see the top): the smaller of the two largest floats below 1,
// and the float cells of x that the gap 1 - u may span (as roundtrip.cpp).
constexpr float kTopTwoFloats = 0x1.fffffcp-1f;
constexpr double kCellFactor = 4.0;

// Position of x in the order of floats (-0 just below +0): the difference of two
// keys is their distance in ulps.
int64_t ordered_key(float x) {
    const uint32_t b = float_to_bits(x);
    return (b & kFloatSignMask) ? -static_cast<int64_t>(b & ~kFloatSignMask) - 1 : static_cast<int64_t>(b);
}

struct FailureExample {
    float u = 0.0f, x = 0.0f, back = 0.0f;
};
struct BadPdfExample {
    float u = 0.0f, x = 0.0f;
    double pdf = 0.0;
};

struct ChunkStats {
    Tally<FailureExample> failures;  // first in u (the index is u's bit pattern)
    Tally<FailureExample> outside;   // invert(x) outside [0,1), not NaN, not u rounded to 1
    Tally<FailureExample> rounded_to_one;
    Tally<BadPdfExample> bad_pdf;
    uint64_t steps_up = 0, steps_down = 0;
    uint64_t boundary_zero = 0;               // pdf exactly 0 at an output on the domain's boundary
    uint64_t max_up_ulps = 0, max_down_ulps = 0;  // largest step in each direction, in ulps of the output
    double max_error = 0.0;
    float first_x = 0.0f, last_x = 0.0f;
};

// ---- compute: one chunk of consecutive floats u, then the chunks in order ----

// One consecutive step previous -> x of sample, counted in its direction with
// its size in ulps.
void count_step(ChunkStats& s, float previous, float x) {
    const auto ulps = static_cast<uint64_t>(std::abs(ordered_key(x) - ordered_key(previous)));
    if (x > previous) {
        ++s.steps_up;
        s.max_up_ulps = std::max(s.max_up_ulps, ulps);
    } else if (x < previous) {
        ++s.steps_down;
        s.max_down_ulps = std::max(s.max_down_ulps, ulps);
    }
}

// The round trip and pdf of one input u -> x (-> back, pdf).
void check_one(ChunkStats& s, const chi2::Domain& domain, double tol, float u, float x, float back, double pdf) {
    const double err = std::abs(static_cast<double>(back) - u);
    if (!(err <= s.max_error)) s.max_error = err;  // NaN sticks
    if (!(err <= tol)) s.failures.add(float_to_bits(u), {u, x, back});
    if (back == 1.0f && (u >= kTopTwoFloats || 1.0 - u <= kCellFactor * pdf * float_spacing(x)))
        s.rounded_to_one.add(float_to_bits(u), {u, x, back});
    else if (!(back >= 0.0f && back < 1.0f) && !std::isnan(back))
        s.outside.add(float_to_bits(u), {u, x, back});
    if (pdf == 0.0 && domain.on_boundary(chi2::DomainPoint{static_cast<double>(x), 0.0, 0.0})) {
        ++s.boundary_zero;
    } else if (!(std::isfinite(pdf) && pdf > 0.0)) {
        s.bad_pdf.add(float_to_bits(u), {u, x, pdf});
    }
}

ChunkStats scan_chunk(const WarpCase& warp, double tol, std::size_t c) {
    ChunkStats s;
    std::vector<WarpInput> in(kBatch), back(kBatch);
    std::vector<WarpOutput> x(kBatch);
    std::vector<double> pdf(kBatch);
    const uint32_t begin = static_cast<uint32_t>(c) * kChunk;
    const uint32_t end = std::min(kUnitFloats, begin + kChunk);
    bool first = true;
    float previous = 0.0f;
    for (uint32_t at = begin; at < end; at += kBatch) {
        const std::size_t n = std::min<std::size_t>(kBatch, end - at);
        const std::span<WarpInput> ins(in.data(), n);
        const std::span<WarpOutput> xs(x.data(), n);
        for (std::size_t i = 0; i < n; ++i) in[i] = WarpInput{{bits_to_float(at + static_cast<uint32_t>(i)), 0.0f}, 0};
        warp.sample(ins, xs);
        warp.invert(xs, std::span<WarpInput>(back.data(), n));
        warp.pdf(xs, std::span<double>(pdf.data(), n));
        for (std::size_t i = 0; i < n; ++i) {
            const float xi = x[i][0];
            check_one(s, warp.domain(), tol, in[i].u[0], xi, back[i].u[0], pdf[i]);
            if (first) {
                s.first_x = xi;
                first = false;
            } else {
                count_step(s, previous, xi);
            }
            previous = xi;
        }
    }
    s.last_x = previous;
    return s;
}

// Chunk order: the step across each chunk border is counted here, and the first
// examples are the first in u.
ChunkStats merge_chunks(const std::vector<ChunkStats>& stats) {
    ChunkStats t;
    for (std::size_t c = 0; c < stats.size(); ++c) {
        const ChunkStats& s = stats[c];
        if (c > 0) count_step(t, stats[c - 1].last_x, s.first_x);
        t.failures.merge(s.failures);
        t.outside.merge(s.outside);
        t.rounded_to_one.merge(s.rounded_to_one);
        t.bad_pdf.merge(s.bad_pdf);
        t.boundary_zero += s.boundary_zero;
        t.max_up_ulps = std::max(t.max_up_ulps, s.max_up_ulps);
        t.max_down_ulps = std::max(t.max_down_ulps, s.max_down_ulps);
        t.steps_up += s.steps_up;
        t.steps_down += s.steps_down;
        if (!(s.max_error <= t.max_error)) t.max_error = s.max_error;
    }
    return t;
}

// ---- judge: the case's own round-trip tolerance (its documented float error)
// and kWobbleUlps for steps back; a bad pdf off the boundary fails outright ----

// The reasons about where invert(x) lies: outside [0,1), or 1.0 for u rounded
// to 1 under --strict.
void domain_reasons(std::vector<std::string>& why, const ChunkStats& t, bool strict) {
    if (t.outside.first) {
        const FailureExample& e = *t.outside.first;
        why.push_back(fmt::format("{} inputs: invert(x) is outside the input domain [0,1), first u = {:a} -> x = {} "
                                  "-> {:a}",
                                  t.outside.count, e.u, e.x, e.back));
    }
    if (strict && t.rounded_to_one.first) {
        const FailureExample& e = *t.rounded_to_one.first;
        why.push_back(fmt::format("{} inputs: invert(x) == 1.0 for u at the edge of 1 (u rounded to 1), first u = "
                                  "{:a}: passes by default, fails under --strict",
                                  t.rounded_to_one.count, e.u));
    }
}

CheckResult judge(const ChunkStats& t, double tol, bool strict) {
    CheckResult r;
    r.samples = kUnitFloats;
    r.figures = {{"inputs", static_cast<double>(kUnitFloats)},
                 {"max_error", t.max_error},
                 {"tolerance", tol},
                 {"roundtrip_failures", static_cast<double>(t.failures.count)},
                 {"bad_pdf", static_cast<double>(t.bad_pdf.count)},
                 {"steps_up", static_cast<double>(t.steps_up)},
                 {"steps_down", static_cast<double>(t.steps_down)}};
    // The direction is that of the majority of steps; the others step back.
    const bool increasing = t.steps_up >= t.steps_down;
    const uint64_t steps_back = increasing ? t.steps_down : t.steps_up;
    const uint64_t max_back = increasing ? t.max_down_ulps : t.max_up_ulps;
    r.figures.push_back({"boundary_zero_pdf", static_cast<double>(t.boundary_zero)});
    r.figures.push_back({"steps_back", static_cast<double>(steps_back)});
    r.figures.push_back({"max_step_back_ulps", static_cast<double>(max_back)});
    r.figures.push_back({"wobble_tolerance_ulps", static_cast<double>(kWobbleUlps)});
    r.figures.push_back({"outside_input_domain", static_cast<double>(t.outside.count)});
    r.figures.push_back({"rounded_to_one", static_cast<double>(t.rounded_to_one.count)});
    r.figures.push_back({"strict", strict ? 1.0 : 0.0});
    const bool non_monotone = max_back > kWobbleUlps;
    r.summary = fmt::format("max |du| {:.2e} over all {} floats", t.max_error, kUnitFloats);
    if (steps_back > 0)
        r.summary += fmt::format(", {} steps back (largest {} ulps)", steps_back, max_back);
    if (t.boundary_zero > 0) r.summary += fmt::format(", {} zero pdfs on the boundary", t.boundary_zero);
    if (t.rounded_to_one.count > 0)
        r.summary += fmt::format(", {} rounded to 1 ({})", t.rounded_to_one.count,
                                 strict ? "failed: --strict" : "fails under --strict");
    std::vector<std::string> why;
    if (t.failures.first) {
        const FailureExample& e = *t.failures.first;
        why.push_back(fmt::format("{} inputs come back further than {:.3g}, first u = {:a} -> x = {} -> {:a}",
                                  t.failures.count, tol, e.u, e.x, e.back));
    }
    domain_reasons(why, t, strict);
    if (t.bad_pdf.first) {
        const BadPdfExample& e = *t.bad_pdf.first;
        why.push_back(fmt::format("{} samples with a pdf that is not finite and positive (off the domain's "
                                  "boundary), first u = {:a} -> x = {} (pdf {})",
                                  t.bad_pdf.count, e.u, e.x, e.pdf));
    }
    if (non_monotone)
        why.push_back(fmt::format("sample is not monotone: {} steps up and {} steps down between consecutive "
                                  "floats u, stepping back by up to {} ulps (rounding wobble is at most {})",
                                  t.steps_up, t.steps_down, max_back, kWobbleUlps));
    r.verdict = why.empty() ? Verdict::Pass : Verdict::Fail;
    r.message = join_reasons(why);
    return r;
}

class ExhaustiveRoundtripCheck final : public Check {
public:
    std::string name() const override { return "exhaustive_roundtrip"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"max_error", "largest |invert(sample(u)) \u2212 u|", FigureRule::AtMost, "tolerance"},
                 {"roundtrip_failures", "floats beyond the tolerance", FigureRule::Zero},
                 {"bad_pdf", "samples with a pdf that is not finite and positive", FigureRule::Zero},
                 {"max_step_back_ulps", "largest step back of sample(u), ulps", FigureRule::AtMost, "wobble_tolerance_ulps"},
                 {"outside_input_domain", "inverses outside [0, 1)", FigureRule::Zero},
                 {"rounded_to_one", "u rounded to 1 (excused; fails under --strict)", FigureRule::Counted}},
                .bounds = [](const CheckResult& r, std::vector<JudgedQuantity>& out) {
                    strict_zero_line(r, "rounded_to_one", "u rounded to 1", out);
                }};
    }
    bool uses_seed() const override { return false; }  // every input, no random stream
    CheckLegend legend() const override {
        return {name(), "Every float u of [0, 1): the round trip, a monotone sample(u), a finite positive pdf.",
                ""};
    }
    std::string description() const override {
        return "1D warps, every float u of [0,1): invert(sample(u)) vs u, monotone sample, finite positive pdf "
               "(--exhaustive)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        if (warp.input_kind() != InputKind::Uniform1D) return Applicability::not_about_such_cases();
        return warp.has_inverse() ? Applicability::runs() : Applicability::lacks("the warp has no inverse");
    }
    bool runs_by_default(const RunOptions& options) const override { return options.exhaustive; }
    double time_budget(const RunOptions& options) const override { return sweep_time_budget(options, kUnitFloats); }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const double tol = warp.info().roundtrip_tolerance;
        const std::size_t chunks = (kUnitFloats + kChunk - 1) / kChunk;
        std::vector<ChunkStats> stats(chunks);
        ctx.parallel_for(chunks, [&](std::size_t c) {
            ctx.throw_if_cancelled();  // a cancelled or over-budget run stops at the next chunk
            stats[c] = scan_chunk(warp, tol, c);
        });
        return judge(merge_chunks(stats), tol, ctx.options().strict);
    }
};

}  // namespace

std::unique_ptr<Check> make_exhaustive_roundtrip_check() { return std::make_unique<ExhaustiveRoundtripCheck>(); }

}  // namespace warpcheck
