// "repeatability" and "bsdf_repeatability": a sampler is a function of its inputs. Every case's sample
// (with what it returns beside the point: its pdf, weight, f, L) and its pdf
// at the sample are computed twice on the same inputs: first in chunks spread
// over the run's threads, then again chunk by chunk, last chunk first, on one
// thread, each chunk's inputs in reverse order. Every value must come back
// with the same bits.
//
// What it catches, that no distribution test can: state the inputs do not
// carry. A sampler that draws from a generator of its own (rand(), a member
// or thread-local RNG), a cache keyed on part of its input, a scratch buffer
// shared between threads, a table built from the first call's arguments: its
// outputs can follow the right law (chi2 and unbinned pass), while a renderer
// that feeds it stratified or low-discrepancy points gets neither their
// convergence nor a reproducible image, and warpcheck's own promise (the same
// seed gives the same numbers on any thread count) no longer holds for it.
//
// The rule has no tolerance: the same code on the same bits must give the
// same bits, and a float difference of one ulp is as much a sign of hidden
// state as a large one. The comparison is of the bit patterns (+0 against -0
// is a difference), except that a NaN equals nothing, not even its own bits:
// an output that is NaN cannot be shown to repeat, so it fails here as in
// every other comparison of warpcheck (counted apart, as nan_inputs).
//
// Batch shape is kept: each chunk is passed whole both times, and the
// reversal leaves the chunk's last (size mod 64) inputs in place, so an input
// that a batched sampler of 4 to 64 lanes (16 floats of AVX-512, unrolled up
// to 4 times) computes in its scalar tail is computed there both times, and a
// sampler whose SIMD body and tail round differently is not mistaken for one
// with state. Reversing within the chunk
// is what reaches state carried from one call to the next (a memo of the last
// call): in the same order, only each chunk's first call would see it.
//
// The one excuse: a stochastic BSDF (BsdfClaims::stochastic, pbrt-v4's
// LayeredBxDF) returns f as a random-walk estimate; its f may differ between
// calls and is counted (excused_values), never judged. Its sampled direction
// and pdf are held to the rule like any other's.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "validate/api/bsdf_case.h"
#include "validate/api/light_case.h"
#include "validate/checks/repeatability/repeatability_check.h"
#include "validate/checks/shared/formatting.h"
#include "validate/checks/shared/input_chunks.h"

namespace warpcheck {
namespace {

/// Random inputs compared (plus the edge inputs): 2^16, or the run's sample
/// count if smaller. A sampler whose state changes a share q of its outputs
/// escapes with probability (1 - q)^N, so 90% power needs q >= ln(10) / N =
/// 3.5e-5, one call in 28,000, where the state this check is for (a generator
/// of its own, a stale cache entry, a race) touches most calls; more inputs
/// would cost validate --all a second per 2^16.
constexpr uint64_t kRepeatInputs = uint64_t{1} << 16;

/// What one input gave, each value widened exactly to double: the point's
/// three coordinates, then what the sample returned and the pdf at the point.
constexpr std::size_t kSlots = 8;
enum Slot : std::size_t { kX = 0, kY = 1, kZ = 2, kReturned = 3, kPdf = 4, kExtra = 5, kFlags = 6, kPdfAt = 7 };
const char* const kSlotNames[kSlots] = {"x", "y", "z", "returned value", "returned pdf", "eta or distance",
                                        "flags", "pdf at the sample"};

struct Observed {
    std::vector<WarpInput> inputs;
    std::vector<double> values;  ///< kSlots per input
};

bool returns_value(SampleReturns r) {
    return r == SampleReturns::PointAndPdf || r == SampleReturns::PointAndWeight ||
           r == SampleReturns::IndexAndRemappedU;
}

/// The case's outputs on `in`, kSlots per input (0 where a slot does not apply).
std::vector<double> observe(const WarpCase& warp, std::span<const WarpInput> in) {
    std::vector<double> v(in.size() * kSlots, 0.0);
    std::vector<WarpOutput> x(in.size());
    std::vector<unsigned char> sampled(in.size(), 1);
    if (const BsdfCase* b = as_bsdf(warp)) {
        std::vector<BsdfRecord> r(in.size());
        b->sample_bsdf(in, r);
        for (std::size_t i = 0; i < in.size(); ++i) {
            x[i] = r[i].wi;
            sampled[i] = r[i].sampled();
            v[i * kSlots + kReturned] = r[i].f;
            v[i * kSlots + kPdf] = r[i].pdf;
            v[i * kSlots + kExtra] = r[i].eta;
            v[i * kSlots + kFlags] = static_cast<double>(static_cast<unsigned>(r[i].flags));
        }
    } else if (const LightCase* l = as_light(warp)) {
        std::vector<LightRecord> r(in.size());
        l->sample_light(in, r);
        for (std::size_t i = 0; i < in.size(); ++i) {
            x[i] = r[i].wi;
            sampled[i] = r[i].sampled();
            v[i * kSlots + kReturned] = r[i].L;
            v[i * kSlots + kPdf] = r[i].pdf;
            v[i * kSlots + kExtra] = r[i].distance;
        }
    } else if (returns_value(warp.sample_returns())) {
        std::vector<double> value(in.size());
        warp.sample_with_value(in, x, value);
        for (std::size_t i = 0; i < in.size(); ++i) v[i * kSlots + kReturned] = value[i];
    } else {
        warp.sample(in, x);
    }
    for (std::size_t i = 0; i < in.size(); ++i)
        for (std::size_t c = 0; c < 3; ++c) v[i * kSlots + c] = x[i][c];
    if (warp.has_pdf()) {
        // The pdf where there is a sample: a declined light or BSDF sample's
        // direction is no point of the domain.
        std::vector<WarpOutput> at;
        std::vector<std::size_t> index;
        for (std::size_t i = 0; i < in.size(); ++i)
            if (sampled[i]) at.push_back(x[i]), index.push_back(i);
        std::vector<double> pdf(at.size());
        warp.pdf(at, pdf);
        for (std::size_t k = 0; k < at.size(); ++k) v[index[k] * kSlots + kPdfAt] = pdf[k];
    }
    return v;
}

/// Inputs before this index of a chunk of n are reversed on the second pass;
/// the rest, the scalar tail of a sampler of up to 64 lanes, stay where they were.
std::size_t reversed_prefix(std::size_t n) { return n - n % 64; }

/// The chunk's inputs in the second pass's order.
std::vector<WarpInput> second_order(const std::vector<WarpInput>& in) {
    std::vector<WarpInput> out(in);
    std::reverse(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(reversed_prefix(in.size())));
    return out;
}

/// Outputs of second_order's inputs put back in the first pass's order.
std::vector<double> first_order(std::vector<double> v) {
    const std::size_t m = reversed_prefix(v.size() / kSlots);
    for (std::size_t i = 0, j = m; i + 1 < j; ++i, --j)
        std::swap_ranges(v.begin() + static_cast<std::ptrdiff_t>(i * kSlots),
                         v.begin() + static_cast<std::ptrdiff_t>((i + 1) * kSlots),
                         v.begin() + static_cast<std::ptrdiff_t>((j - 1) * kSlots));
    return v;
}

/// Whether p and q are the same value: the same bits, and not NaN.
bool same(double p, double q) { return std::bit_cast<uint64_t>(p) == std::bit_cast<uint64_t>(q) && !std::isnan(p); }

/// Whether a's slot may differ from b's: a stochastic BSDF's f, an estimate.
bool excused_slot(const WarpCase& warp, std::size_t slot) {
    if (slot != kReturned) return false;
    if (const BsdfCase* b = as_bsdf(warp)) return b->claims().stochastic;
    if (const MisCase* m = as_mis(warp)) return m->bsdf().claims().stochastic;
    return false;
}

struct Differences {
    uint64_t inputs = 0, differing = 0, excused = 0, nan = 0;
    std::vector<uint64_t> per_slot = std::vector<uint64_t>(kSlots, 0);
    bool has_example = false;
    WarpInput input{};
    std::vector<double> first, second;
};

void compare(const WarpCase& warp, const Observed& a, const std::vector<double>& b, Differences& d) {
    for (std::size_t i = 0; i < a.inputs.size(); ++i) {
        ++d.inputs;
        bool differs = false, excused = false, nan = false;
        for (std::size_t s = 0; s < kSlots; ++s) {
            const double p = a.values[i * kSlots + s], q = b[i * kSlots + s];
            if (same(p, q)) continue;
            if (excused_slot(warp, s)) {
                excused = true;
                continue;
            }
            ++d.per_slot[s];
            differs = true;
            nan = nan || std::isnan(p) || std::isnan(q);
        }
        d.excused += excused && !differs;
        d.nan += nan;
        if (!differs) continue;
        ++d.differing;
        if (d.has_example) continue;
        d.has_example = true;
        d.input = a.inputs[i];
        d.first.assign(a.values.begin() + static_cast<std::ptrdiff_t>(i * kSlots),
                       a.values.begin() + static_cast<std::ptrdiff_t>((i + 1) * kSlots));
        d.second.assign(b.begin() + static_cast<std::ptrdiff_t>(i * kSlots),
                        b.begin() + static_cast<std::ptrdiff_t>((i + 1) * kSlots));
    }
}

std::string describe_example(const WarpCase& warp, const Differences& d) {
    std::string s = fmt::format("input {}:", format_input(d.input, warp.input_kind()));
    for (std::size_t k = 0; k < kSlots; ++k)
        if (!same(d.first[k], d.second[k]) && !excused_slot(warp, k))
            s += fmt::format(" {} {:.9g} then {:.9g};", kSlotNames[k], d.first[k], d.second[k]);
    s.pop_back();
    return s;
}

CheckResult judge(const WarpCase& warp, const Differences& d) {
    CheckResult r;
    r.samples = d.inputs;
    const uint64_t point = d.per_slot[kX] + d.per_slot[kY] + d.per_slot[kZ];
    const uint64_t returned = d.per_slot[kReturned] + d.per_slot[kPdf] + d.per_slot[kExtra] + d.per_slot[kFlags];
    r.figures = {{"inputs", static_cast<double>(d.inputs)},
                 {"differing_inputs", static_cast<double>(d.differing)},
                 {"differing_points", static_cast<double>(point)},
                 {"differing_returned", static_cast<double>(returned)},
                 {"differing_pdf", static_cast<double>(d.per_slot[kPdfAt])},
                 {"nan_inputs", static_cast<double>(d.nan)},
                 {"excused_values", static_cast<double>(d.excused)},
                 {"detectable_share", std::log(10.0) / static_cast<double>(std::max<uint64_t>(d.inputs, 1))}};
    const std::string excused =
        d.excused > 0 ? fmt::format("; {} estimates of a stochastic f differed (not judged)", d.excused) : "";
    if (d.differing == 0) {
        r.verdict = Verdict::Pass;
        r.summary = fmt::format("{} inputs twice: identical bits{}", d.inputs, excused);
        r.message = fmt::format("every one of {} inputs (edges and random, in chunks on the job's threads, then again "
                                "in reverse order on one thread) gave the same bits both times{}; state touching 1 "
                                "call in {:.2g} would show with 90% probability",
                                d.inputs, excused, 1.0 / *r.figure("detectable_share"));
        return r;
    }
    r.verdict = Verdict::Fail;
    if (d.nan == d.differing) {  // nothing changed but NaN, which equals nothing
        r.summary = fmt::format("{} of {} inputs gave NaN: not shown to repeat", d.nan, d.inputs);
        r.message = fmt::format("{} of {} inputs gave NaN (points {}, returned values {}, pdf {}): a NaN equals no "
                                "value, its own bits included, so these outputs cannot be shown to repeat; first: "
                                "{}{}",
                                d.nan, d.inputs, point, returned, d.per_slot[kPdfAt], describe_example(warp, d),
                                excused);
        return r;
    }
    r.summary = fmt::format("{} of {} inputs gave other outputs the second time", d.differing, d.inputs);
    r.message = fmt::format("{} of {} inputs gave other bits when computed again (points {}, returned values {}, "
                            "pdf {}): the sampler keeps state its inputs do not carry (its own random generator, a "
                            "cache, a race between threads){}; first: {}{}",
                            d.differing, d.inputs, point, returned, d.per_slot[kPdfAt],
                            d.nan > 0 ? fmt::format(" ({} of them NaN)", d.nan) : "", describe_example(warp, d),
                            excused);
    return r;
}

/// One rule, two checks: the runner gives BSDF cases only to the checks about
/// BSDFs (Check::about_bsdfs), every other case to the rest.
class RepeatabilityCheck final : public Check {
public:
    explicit RepeatabilityCheck(bool bsdfs) : bsdfs_(bsdfs) {}
    std::string name() const override { return bsdfs_ ? "bsdf_repeatability" : "repeatability"; }
    bool about_bsdfs() const override { return bsdfs_; }
    std::string description() const override {
        return "the same inputs give the same outputs, bit for bit: sample, what it returns and the pdf, computed "
               "in chunks on the job's threads and again in reverse order";
    }
    CheckLegend legend() const override {
        return {name(), "Every input's sample, the values it returns and the pdf at it, computed twice (in chunks "
                "on the job's threads, then in reverse order on one thread, each chunk as a batch of the same "
                "size), must have the same bits: any difference is state the inputs do not carry, and a NaN, "
                "which equals nothing, fails. A stochastic BSDF's f estimates are counted, not judged.",
                ""};
    }
    JudgedRules judged_rules() const override {
        return {.figures = {{"differing_inputs", "inputs whose outputs changed when computed again, or were NaN",
                             FigureRule::Zero}}};
    }
    Applicability applicability(const WarpCase&) const override { return Applicability::runs(); }
    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const uint64_t n = std::min<uint64_t>(ctx.options().samples, kRepeatInputs);
        // First: chunks spread over the threads, in whatever order they run.
        const std::vector<Observed> first = map_input_chunks<Observed>(
            ctx, warp.input_kind(), n, true, [&](std::size_t, std::span<const WarpInput> in) {
                return Observed{{in.begin(), in.end()}, observe(warp, in)};
            });
        // Then: each chunk again, last first, on this thread, its inputs reversed.
        Differences d;
        for (std::size_t c = first.size(); c-- > 0;) {
            ctx.throw_if_cancelled();
            compare(warp, first[c], first_order(observe(warp, second_order(first[c].inputs))), d);
        }
        return judge(warp, d);
    }

private:
    bool bsdfs_;
};

}  // namespace

std::unique_ptr<Check> make_repeatability_check() { return std::make_unique<RepeatabilityCheck>(false); }
std::unique_ptr<Check> make_bsdf_repeatability_check() { return std::make_unique<RepeatabilityCheck>(true); }

}  // namespace warpcheck
