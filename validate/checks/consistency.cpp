// Sample/pdf consistency: every sample lies in the domain and has a finite,
// positive density. Each kind of violation is counted and reported on its own.
// For a sampler that returns its pdf and has no pdf function, the density of
// a sample is the one returned with it.
//
// Slack, stated: planar points may overshoot the unit circle by 1e-6 (float
// cos/sin of a radius-1 point); directions may differ from unit length by 1e-5
// (float normalisation loses a few ulps; a missing normalisation is off by far
// more); intervals and boxes are closed and exact. A zero density is accepted
// only for samples exactly on the domain's boundary, where a density can vanish
// legitimately (the cosine hemisphere at z = 0, reached from u.x = 0); how many
// were accepted that way is reported.
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "validate/checks/checks.h"
#include "validate/checks/evidence.h"
#include "validate/checks/formatting.h"
#include "validate/checks/input_chunks.h"

namespace warpcheck {
namespace {

struct Example {
    WarpInput input;
    WarpOutput output{};
    double pdf = 0.0;
};

struct Stats {
    uint64_t count = 0;
    Tally<Example> nan_sample, outside, bad_pdf, zero_pdf;
    uint64_t boundary_zero = 0;
    double min_pdf = std::numeric_limits<double>::infinity();
    double max_pdf = 0.0;

    void merge(const Stats& o) {
        count += o.count;
        nan_sample.merge(o.nan_sample);
        outside.merge(o.outside);
        bad_pdf.merge(o.bad_pdf);
        zero_pdf.merge(o.zero_pdf);
        boundary_zero += o.boundary_zero;
        min_pdf = std::min(min_pdf, o.min_pdf);
        max_pdf = std::max(max_pdf, o.max_pdf);
    }
};

bool finite_point(const chi2::DomainPoint& p, int dims) {
    for (int k = 0; k < dims; ++k)
        if (!std::isfinite(p[static_cast<std::size_t>(k)])) return false;
    return true;
}

/// Sorts one sample into the kinds of violation (or none).
void classify(Stats& s, const chi2::Domain& domain, uint64_t index, const Example& e) {
    ++s.count;
    const chi2::DomainPoint p = to_domain_point(e.output);
    if (!finite_point(p, domain.point_dimension())) {
        s.nan_sample.add(index, e);
        return;
    }
    if (!domain.contains(p)) s.outside.add(index, e);
    if (!std::isfinite(e.pdf) || e.pdf < 0.0) {
        s.bad_pdf.add(index, e);
    } else if (e.pdf == 0.0) {
        if (domain.on_boundary(p)) ++s.boundary_zero;
        else s.zero_pdf.add(index, e);
    } else {
        s.min_pdf = std::min(s.min_pdf, e.pdf);
        s.max_pdf = std::max(s.max_pdf, e.pdf);
    }
}

Stats compute(const WarpCase& warp, const CheckContext& ctx) {
    const chi2::Domain& domain = warp.domain();
    auto parts = map_input_chunks<Stats>(ctx, warp.input_kind(), ctx.options().samples, true,
                                         [&](std::size_t chunk, std::span<const WarpInput> inputs) {
        Stats s;
        std::vector<WarpOutput> x(inputs.size());
        std::vector<double> pdf(inputs.size());
        if (warp.has_pdf()) {
            warp.sample(inputs, x);
            warp.pdf(x, pdf);
        } else {
            warp.sample_with_value(inputs, x, pdf);  // the pdf that sample returns
        }
        for (std::size_t i = 0; i < inputs.size(); ++i)
            classify(s, domain, chunk * kInputChunkSize + i, {inputs[i], x[i], pdf[i]});
        return s;
    });
    return merge_in_order(parts);
}

struct Finding {
    const Tally<Example>* tally;
    std::string what;
};

/// The kinds of violation in the order the verdict states them.
std::vector<Finding> findings(const Stats& s, const chi2::Domain& domain) {
    return {{&s.nan_sample, "samples with NaN or infinite coordinates"},
            {&s.outside, fmt::format("samples outside the {}", domain.describe())},
            {&s.bad_pdf, "samples with a NaN, infinite or negative pdf"},
            {&s.zero_pdf, "samples with pdf 0 inside the domain"}};
}

/// The verdict: any sample of any kind of violation fails; there is no
/// tolerance on counts, since a correct warp produces none.
void judge_and_explain(CheckResult& r, const Stats& s, const WarpCase& warp) {
    const int dims = warp.domain().point_dimension();
    const InputKind kind = warp.input_kind();
    Table examples{"First violation of each kind", {"violation", "count", "input u", "sample(u)", "pdf"}, {}};
    std::vector<std::string> problems;
    for (const Finding& f : findings(s, warp.domain())) {
        if (f.tally->count == 0) continue;
        const Example& e = *f.tally->first;
        problems.push_back(fmt::format("{} {} (e.g. u = {} -> x = {}, pdf {:.6g})", f.tally->count, f.what,
                                       format_input(e.input, kind), format_output(e.output, dims), e.pdf));
        examples.rows.push_back({f.what, std::to_string(f.tally->count), format_input(e.input, kind),
                                 format_output(e.output, dims), fmt::format("{:.6g}", e.pdf)});
    }
    r.verdict = problems.empty() ? Verdict::Pass : Verdict::Fail;
    if (problems.empty()) {
        r.summary = fmt::format("pdf in [{:.3g}, {:.3g}]", s.min_pdf, s.max_pdf);
        if (s.boundary_zero > 0) r.summary += fmt::format(", {} zero on boundary", s.boundary_zero);
        return;
    }
    r.summary = problems.front().substr(0, problems.front().find(" (e.g."));
    r.message = join_reasons(problems);
    r.tables.push_back(std::move(examples));
}

void add_figures(CheckResult& r, const Stats& s) {
    r.samples = s.count;
    r.figures = {{"samples", static_cast<double>(s.count)},
                 {"non_finite_samples", static_cast<double>(s.nan_sample.count)},
                 {"outside_domain", static_cast<double>(s.outside.count)},
                 {"non_finite_or_negative_pdf", static_cast<double>(s.bad_pdf.count)},
                 {"zero_pdf", static_cast<double>(s.zero_pdf.count)},
                 {"zero_pdf_on_boundary", static_cast<double>(s.boundary_zero)},
                 {"min_pdf", s.min_pdf},
                 {"max_pdf", s.max_pdf}};
}

class ConsistencyCheck final : public Check {
public:
    std::string name() const override { return "consistency"; }
    std::string description() const override {
        return "every sample lies in the domain and has a finite, positive pdf (edge inputs included)";
    }
    bool applies_to(const WarpCase& warp) const override { return !warp.is_discrete(); }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const Stats stats = compute(warp, ctx);
        CheckResult r;
        add_figures(r, stats);
        judge_and_explain(r, stats, warp);
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_consistency_check() { return std::make_unique<ConsistencyCheck>(); }

}  // namespace warpcheck
