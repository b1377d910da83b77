// Round trip: invert(sample(u)) must give u back.
//
// Uniform inputs: the error is max_k |invert(sample(u))_k - u_k|, compared with
// the case's tolerance. Where the warp is not injective (the azimuth at a pole,
// the centre of a disk) any preimage is as good as u; so when the input-space
// error is large, the output-space error |sample(invert(x)) - x| decides, and
// such points are counted as degenerate instead of failing.
// Raw-bit inputs: the inverse must be exact: sample(invert(x)) == x, and
// invert(x) is the first preimage, so invert(x) <= the bits that produced x.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "validate/checks/checks.h"
#include "validate/checks/formatting.h"
#include "validate/checks/input_chunks.h"

namespace warpcheck {
namespace {

constexpr std::size_t kWorstKept = 10;
constexpr int kFirstDecade = -10;  // error histogram: decades 1e-10 .. 1e0
constexpr int kDecades = 11;

struct Worst {
    double error = 0.0;
    uint64_t index = 0;  // position in the input order (edges first)
    WarpInput input;
    WarpOutput output{};
    WarpInput back;
};

struct Stats {
    uint64_t count = 0;
    uint64_t failures = 0;
    uint64_t degenerate = 0;
    uint64_t exact = 0;
    double max_error = 0.0;  // over non-degenerate points; NaN/inf errors count as failures
    std::array<uint64_t, kDecades + 2> histogram{};  // [0]: below 1e-10 (not exact), [1..11]: decades, [12]: >= 10
    std::vector<Worst> worst;                          // failures first, then largest errors

    void keep(const Worst& w, bool failed) {
        // Order: failures before passes, then larger error, then earlier index.
        worst.push_back(w);
        worst.back().error = failed ? std::numeric_limits<double>::infinity() : w.error;
        worst.back().index = w.index;
        auto order = [](const Worst& a, const Worst& b) {
            const double ea = std::isnan(a.error) ? std::numeric_limits<double>::infinity() : a.error;
            const double eb = std::isnan(b.error) ? std::numeric_limits<double>::infinity() : b.error;
            return ea != eb ? ea > eb : a.index < b.index;
        };
        std::sort(worst.begin(), worst.end(), order);
        if (worst.size() > kWorstKept) worst.resize(kWorstKept);
    }
};

double max_abs_diff(const WarpOutput& a, const WarpOutput& b, int dims) {
    double d = 0.0;
    for (int k = 0; k < dims; ++k) {
        const double e = std::abs(static_cast<double>(a[k]) - static_cast<double>(b[k]));
        if (!(e <= d)) d = e;  // NaN propagates into d
    }
    return d;
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
        const bool bits = takes_bits(kind);
        const int in_dims = input_dimension(kind);
        const int out_dims = warp.domain().point_dimension();
        const double tol = warp.info().roundtrip_tolerance;
        const uint64_t samples = ctx.options().samples;

        auto chunk_stats = map_input_chunks<Stats>(ctx, kind, samples, true, [&](std::size_t chunk, auto inputs) {
            Stats s;
            std::vector<WarpOutput> x(inputs.size()), x2(inputs.size());
            std::vector<WarpInput> back(inputs.size());
            warp.sample(inputs, x);
            warp.invert(x, back);
            warp.sample(back, x2);
            const uint64_t base = chunk * kInputChunkSize;  // edge inputs first, then the random stream
            for (std::size_t i = 0; i < inputs.size(); ++i) {
                double err;
                bool failed, degenerate = false;
                if (bits) {
                    const bool same = max_abs_diff(x2[i], x[i], out_dims) == 0.0;
                    const bool first = back[i].bits <= inputs[i].bits;
                    err = static_cast<double>(inputs[i].bits - std::min(inputs[i].bits, back[i].bits));
                    failed = !(same && first);
                } else {
                    err = 0.0;
                    for (int k = 0; k < in_dims; ++k) {
                        const double e = std::abs(static_cast<double>(back[i].u[k]) - inputs[i].u[k]);
                        if (!(e <= err)) err = e;
                    }
                    failed = !(err <= tol);
                    if (failed && max_abs_diff(x2[i], x[i], out_dims) <= tol) {
                        failed = false;
                        degenerate = true;
                    }
                }
                ++s.count;
                if (degenerate) {
                    ++s.degenerate;
                    continue;
                }
                if (failed) ++s.failures;
                if (!bits) {
                    if (err == 0.0) {
                        ++s.exact;
                    } else if (std::isfinite(err)) {
                        const int decade = static_cast<int>(std::floor(std::log10(err)));
                        s.histogram[static_cast<std::size_t>(std::clamp(decade - kFirstDecade + 1, 0, kDecades + 1))]++;
                    }
                }
                if (!(err <= s.max_error)) s.max_error = err;
                if (failed || s.worst.size() < kWorstKept || err > s.worst.back().error)
                    s.keep({err, base + i, inputs[i], x[i], back[i]}, failed);
            }
            return s;
        });

        Stats total;
        for (const Stats& s : chunk_stats) {
            total.count += s.count;
            total.failures += s.failures;
            total.degenerate += s.degenerate;
            total.exact += s.exact;
            if (!(s.max_error <= total.max_error)) total.max_error = s.max_error;
            for (std::size_t k = 0; k < total.histogram.size(); ++k) total.histogram[k] += s.histogram[k];
            for (const Worst& w : s.worst) total.keep(w, std::isinf(w.error));
        }

        CheckResult r;
        r.samples = total.count;
        r.figures = {{"max_error", total.max_error},
                     {"tolerance", bits ? 0.0 : tol},
                     {"failures", static_cast<double>(total.failures)},
                     {"degenerate", static_cast<double>(total.degenerate)},
                     {"exact", static_cast<double>(total.exact)},
                     {"inputs", static_cast<double>(total.count)}};
        r.verdict = total.failures == 0 ? Verdict::Pass : Verdict::Fail;
        if (bits) {
            r.summary = total.failures == 0 ? "exact inverse" : fmt::format("{} inputs not inverted", total.failures);
        } else {
            r.summary = fmt::format("max |du| {:.2e}", total.max_error);
            if (total.degenerate > 0) r.summary += fmt::format(", {} degenerate", total.degenerate);
        }
        if (total.failures > 0) {
            const Worst& w = total.worst.front();
            r.message = bits ? fmt::format("{} of {} inputs: sample(invert(x)) != x or invert(x) is not the first "
                                           "preimage; e.g. bits {} -> x = {} -> invert {}",
                                           total.failures, total.count, format_input(w.input, kind),
                                           format_output(w.output, out_dims), format_input(w.back, kind))
                             : fmt::format("{} of {} inputs come back further than {:.3g} from u; e.g. u = {} -> x = "
                                           "{} -> invert {}",
                                           total.failures, total.count, tol, format_input(w.input, kind),
                                           format_output(w.output, out_dims), format_input(w.back, kind));
        }

        Table worst{"Worst inputs", {"input u", "sample(u)", "invert(sample(u))", bits ? "input offset" : "|du|"}, {}};
        for (const Worst& w : total.worst)
            worst.rows.push_back({format_input(w.input, kind), format_output(w.output, out_dims),
                                  format_input(w.back, kind),
                                  std::isinf(w.error) ? std::string("FAILED") : fmt::format("{:.3e}", w.error)});
        r.tables.push_back(std::move(worst));

        if (!bits) {
            Plot p;
            p.kind = Plot::Kind::Bars;
            p.title = fmt::format("Round-trip error per input (tolerance {:.2e}; {} exact, {} degenerate)", tol,
                                  total.exact, total.degenerate);
            p.x_label = "log10 |invert(sample(u)) - u|";
            p.y_label = "inputs";
            p.log_y = true;
            Series s{"inputs", {}, {}};
            for (int k = 0; k < kDecades + 2; ++k) {
                s.x.push_back(kFirstDecade - 1 + k);
                s.y.push_back(static_cast<double>(total.histogram[static_cast<std::size_t>(k)]));
            }
            p.series.push_back(std::move(s));
            r.plots.push_back(std::move(p));
        }
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_roundtrip_check() { return std::make_unique<RoundtripCheck>(); }

}  // namespace warpcheck
