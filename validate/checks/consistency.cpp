// Sample/pdf consistency: every sample lies in the domain and has a finite,
// positive density. Each kind of violation is counted and reported on its own.
//
// Slack, stated: planar points may overshoot the unit circle by 1e-6 (float
// cos/sin of a radius-1 point); directions may differ from unit length by 1e-5
// (float normalisation loses a few ulps; a missing normalisation is off by far
// more); intervals and boxes are closed and exact. A zero density is accepted
// only for samples exactly on the domain's boundary, where a density can vanish
// legitimately (the cosine hemisphere at z = 0, reached from u.x = 0).
#include <cmath>

#include <fmt/format.h>

#include "validate/checks/checks.h"
#include "validate/checks/formatting.h"
#include "validate/checks/input_chunks.h"

namespace warpcheck {
namespace {

struct Violation {
    uint64_t count = 0;
    bool have_example = false;
    WarpInput input;
    WarpOutput output{};
    double pdf = 0.0;

    void add(const WarpInput& in, const WarpOutput& out, double p) {
        if (count++ == 0) {
            have_example = true;
            input = in;
            output = out;
            pdf = p;
        }
    }
    void merge(const Violation& o) {
        if (o.count == 0) return;
        if (count == 0) *this = o;
        else count += o.count;
    }
};

struct Stats {
    uint64_t count = 0;
    Violation nan_sample, outside, bad_pdf, zero_pdf;
    uint64_t boundary_zero = 0;
    double min_pdf = std::numeric_limits<double>::infinity();
    double max_pdf = 0.0;
};

double domain_slack(const chi2::Domain& d) {
    switch (d.kind) {
        case chi2::DomainKind::SphericalCap: return 1e-5;
        case chi2::DomainKind::Disk: return 1e-6;
        default: return 0.0;
    }
}

class ConsistencyCheck final : public Check {
public:
    std::string name() const override { return "consistency"; }
    std::string description() const override {
        return "every sample lies in the domain and has a finite, positive pdf (edge inputs included)";
    }
    bool applies_to(const WarpCase&) const override { return true; }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const chi2::Domain& domain = warp.domain();
        const int dims = domain.point_dimension();
        const double slack = domain_slack(domain);
        auto chunks = map_input_chunks<Stats>(ctx, warp.input_kind(), ctx.options().samples, true,
                                              [&](std::size_t, auto inputs) {
            Stats s;
            std::vector<WarpOutput> x(inputs.size());
            std::vector<double> pdf(inputs.size());
            warp.sample(inputs, x);
            warp.pdf(x, pdf);
            for (std::size_t i = 0; i < inputs.size(); ++i) {
                ++s.count;
                const chi2::DomainPoint p = to_domain_point(x[i]);
                bool finite_point = true;
                for (int k = 0; k < dims; ++k) finite_point = finite_point && std::isfinite(p[static_cast<std::size_t>(k)]);
                if (!finite_point) {
                    s.nan_sample.add(inputs[i], x[i], pdf[i]);
                    continue;
                }
                if (!domain.contains(p, slack)) s.outside.add(inputs[i], x[i], pdf[i]);
                if (!std::isfinite(pdf[i]) || pdf[i] < 0.0) {
                    s.bad_pdf.add(inputs[i], x[i], pdf[i]);
                } else if (pdf[i] == 0.0) {
                    if (domain.on_boundary(p)) ++s.boundary_zero;
                    else s.zero_pdf.add(inputs[i], x[i], pdf[i]);
                } else {
                    s.min_pdf = std::min(s.min_pdf, pdf[i]);
                    s.max_pdf = std::max(s.max_pdf, pdf[i]);
                }
            }
            return s;
        });

        Stats t;
        for (const Stats& s : chunks) {
            t.count += s.count;
            t.nan_sample.merge(s.nan_sample);
            t.outside.merge(s.outside);
            t.bad_pdf.merge(s.bad_pdf);
            t.zero_pdf.merge(s.zero_pdf);
            t.boundary_zero += s.boundary_zero;
            t.min_pdf = std::min(t.min_pdf, s.min_pdf);
            t.max_pdf = std::max(t.max_pdf, s.max_pdf);
        }

        CheckResult r;
        r.samples = t.count;
        r.figures = {{"samples", static_cast<double>(t.count)},
                     {"non_finite_samples", static_cast<double>(t.nan_sample.count)},
                     {"outside_domain", static_cast<double>(t.outside.count)},
                     {"non_finite_or_negative_pdf", static_cast<double>(t.bad_pdf.count)},
                     {"zero_pdf", static_cast<double>(t.zero_pdf.count)},
                     {"zero_pdf_on_boundary", static_cast<double>(t.boundary_zero)},
                     {"min_pdf", t.min_pdf},
                     {"max_pdf", t.max_pdf}};

        Table examples{"First violation of each kind", {"violation", "count", "input u", "sample(u)", "pdf"}, {}};
        std::vector<std::string> problems;
        auto report = [&](const Violation& v, const char* what) {
            if (v.count == 0) return;
            problems.push_back(fmt::format("{} {} (e.g. u = {} -> x = {}, pdf {:.6g})", v.count, what,
                                           format_input(v.input, warp.input_kind()), format_output(v.output, dims),
                                           v.pdf));
            examples.rows.push_back({what, std::to_string(v.count), format_input(v.input, warp.input_kind()),
                                     format_output(v.output, dims), fmt::format("{:.6g}", v.pdf)});
        };
        report(t.nan_sample, "samples with NaN or infinite coordinates");
        report(t.outside, fmt::format("samples outside the {}", domain.describe()).c_str());
        report(t.bad_pdf, "samples with a NaN, infinite or negative pdf");
        report(t.zero_pdf, "samples with pdf 0 inside the domain");

        r.verdict = problems.empty() ? Verdict::Pass : Verdict::Fail;
        if (problems.empty()) {
            r.summary = fmt::format("pdf in [{:.3g}, {:.3g}]", t.min_pdf, t.max_pdf);
            if (t.boundary_zero > 0) r.summary += fmt::format(", {} zero on boundary", t.boundary_zero);
        } else {
            r.summary = problems.front().substr(0, problems.front().find(" (e.g."));
            for (std::size_t i = 0; i < problems.size(); ++i) r.message += (i ? "; " : "") + problems[i];
            r.tables.push_back(std::move(examples));
        }
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_consistency_check() { return std::make_unique<ConsistencyCheck>(); }

}  // namespace warpcheck
