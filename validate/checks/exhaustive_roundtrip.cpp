// Exhaustive round trip of 1D warps: every float u of [0,1) (1,065,353,216 of
// them, denormals included), not a sample of them.
//
// For each u: x = sample(u), u' = invert(x), p = pdf(x). Counted: round trips
// further than the case's tolerance from u (NaN counts), pdfs that are not
// finite and positive, and steps of sample in each direction between
// consecutive floats u. Verdict: FAIL on any round-trip failure, on any bad pdf,
// or when sample steps both up and down (a 1D inversion warp is monotone,
// increasing or decreasing; steps in both directions break stratification).
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
#include "validate/checks/evidence.h"
#include "validate/checks/formatting.h"

namespace warpcheck {
namespace {

constexpr uint32_t kUnitFloats = 0x3f800000u;  // bit patterns of [0,1): 0 .. 0x3f7fffff
constexpr uint32_t kChunk = uint32_t{1} << 20;
constexpr std::size_t kBatch = 4096;

struct ChunkStats {
    uint64_t failures = 0, bad_pdf = 0, steps_up = 0, steps_down = 0;
    double max_error = 0.0;
    float first_x = 0.0f, last_x = 0.0f;
    bool have_failure = false, have_bad_pdf = false;
    float failure_u = 0.0f, failure_x = 0.0f, failure_back = 0.0f;
    float bad_pdf_u = 0.0f, bad_pdf_x = 0.0f;
    double bad_pdf_value = 0.0;
};

// ---- compute: one chunk of consecutive floats u, then the chunks in order ----

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
            const float u = in[i].u[0];
            const double err = std::abs(static_cast<double>(back[i].u[0]) - u);
            if (!(err <= s.max_error)) s.max_error = err;  // NaN sticks
            if (!(err <= tol)) {
                if (!s.have_failure) {
                    s.have_failure = true;
                    s.failure_u = u;
                    s.failure_x = x[i][0];
                    s.failure_back = back[i].u[0];
                }
                ++s.failures;
            }
            if (!(std::isfinite(pdf[i]) && pdf[i] > 0.0)) {
                if (!s.have_bad_pdf) {
                    s.have_bad_pdf = true;
                    s.bad_pdf_u = u;
                    s.bad_pdf_x = x[i][0];
                    s.bad_pdf_value = pdf[i];
                }
                ++s.bad_pdf;
            }
            const float xi = x[i][0];
            if (first) {
                s.first_x = xi;
                first = false;
            } else {
                s.steps_up += xi > previous;
                s.steps_down += xi < previous;
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
        if (c > 0) {
            t.steps_up += s.first_x > stats[c - 1].last_x;
            t.steps_down += s.first_x < stats[c - 1].last_x;
        }
        t.failures += s.failures;
        t.bad_pdf += s.bad_pdf;
        t.steps_up += s.steps_up;
        t.steps_down += s.steps_down;
        if (!(s.max_error <= t.max_error)) t.max_error = s.max_error;
        if (s.have_failure && !t.have_failure) {
            t.have_failure = true;
            t.failure_u = s.failure_u;
            t.failure_x = s.failure_x;
            t.failure_back = s.failure_back;
        }
        if (s.have_bad_pdf && !t.have_bad_pdf) {
            t.have_bad_pdf = true;
            t.bad_pdf_u = s.bad_pdf_u;
            t.bad_pdf_x = s.bad_pdf_x;
            t.bad_pdf_value = s.bad_pdf_value;
        }
    }

    return t;
}

// ---- judge: no tolerance but the case's own round-trip tolerance (its
// documented float error); a bad pdf or steps in both directions fail outright ----

CheckResult judge(const ChunkStats& t, double tol) {
    CheckResult r;
    r.samples = kUnitFloats;
    r.figures = {{"inputs", static_cast<double>(kUnitFloats)},
                 {"max_error", t.max_error},
                 {"tolerance", tol},
                 {"roundtrip_failures", static_cast<double>(t.failures)},
                 {"bad_pdf", static_cast<double>(t.bad_pdf)},
                 {"steps_up", static_cast<double>(t.steps_up)},
                 {"steps_down", static_cast<double>(t.steps_down)}};
    const bool non_monotone = t.steps_up > 0 && t.steps_down > 0;
    r.verdict = t.failures == 0 && t.bad_pdf == 0 && !non_monotone ? Verdict::Pass : Verdict::Fail;
    r.summary = fmt::format("max |du| {:.2e} over all {} floats", t.max_error, kUnitFloats);
    if (non_monotone) r.summary += fmt::format(", {} up / {} down", t.steps_up, t.steps_down);
    std::vector<std::string> why;
    if (t.failures > 0)
        why.push_back(fmt::format("{} inputs come back further than {:.3g}, first u = {:a} -> x = {} -> {:a}",
                                  t.failures, tol, t.failure_u, t.failure_x, t.failure_back));
    if (t.bad_pdf > 0)
        why.push_back(fmt::format("{} samples with a pdf that is not finite and positive, first u = {:a} -> x = "
                                  "{} (pdf {})",
                                  t.bad_pdf, t.bad_pdf_u, t.bad_pdf_x, t.bad_pdf_value));
    if (non_monotone)
        why.push_back(fmt::format("sample is not monotone: {} steps up and {} steps down between consecutive "
                                  "floats u",
                                  t.steps_up, t.steps_down));
    r.message = join_reasons(why);
    return r;
}

class ExhaustiveRoundtripCheck final : public Check {
public:
    std::string name() const override { return "exhaustive_roundtrip"; }
    bool uses_seed() const override { return false; }  // every input, no random stream
    std::string description() const override {
        return "1D warps, every float u of [0,1): invert(sample(u)) vs u, monotone sample, finite positive pdf "
               "(--exhaustive)";
    }
    bool applies_to(const WarpCase& warp) const override {
        return warp.input_kind() == InputKind::Uniform1D && warp.has_inverse();
    }
    bool runs_by_default(const RunOptions& options) const override { return options.exhaustive; }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const double tol = warp.info().roundtrip_tolerance;
        const std::size_t chunks = (kUnitFloats + kChunk - 1) / kChunk;
        std::vector<ChunkStats> stats(chunks);
        ctx.parallel_for(chunks, [&](std::size_t c) {
            ctx.throw_if_cancelled();  // a cancelled or over-budget run stops at the next chunk
            stats[c] = scan_chunk(warp, tol, c);
        });
        return judge(merge_chunks(stats), tol);
    }
};

}  // namespace

std::unique_ptr<Check> make_exhaustive_roundtrip_check() { return std::make_unique<ExhaustiveRoundtripCheck>(); }

}  // namespace warpcheck
