// Sample/pdf consistency: every sample lies in the domain and has a finite,
// positive density. Each kind of violation is counted and reported on its own.
// For a sampler that returns its pdf and has no pdf function, the density of
// a sample is the one returned with it.
//
// Slack, stated: planar points may overshoot the unit circle by 1e-6 (float
// cos/sin of a radius-1 point); directions may differ from unit length by 1e-5
// (float normalisation loses a few ulps; a missing normalisation is off by far
// more); intervals and boxes are closed and exact. A zero density is accepted
// for samples exactly on the domain's boundary, where a density can vanish
// legitimately (the cosine hemisphere at z = 0, reached from u.x = 0); how many
// were accepted that way is reported, and among random inputs they are bounded
// as the samples rounded across a support's edge are (see boundary_problem).
//
// Supports smaller than the domain (a triangle light inside its bounding
// square, an environment map's empty rows): a correct warp's float arithmetic
// rounds some samples a few ulps across the edge of its density's support,
// where its float pdf is 0. Such a sample is accepted (and counted) when the
// pdf is positive at a point within kProbeUlps float spacings of the domain's
// extent of it in every coordinate, probed along every sign direction (3^d - 1
// of them, so that a straight edge is crossed towards the support whichever
// way it runs). A warp that puts real mass where its pdf is 0 has samples there
// far from any positive pdf, which still fail; and the accepted random samples
// may number at most a Poisson bound (see kRoundedAcrossEdgeRate, or the
// measured share of samples that close to an edge, EdgeBand), edge inputs
// counted apart. Where the support is thinner than a float step (a light's
// corner seen at a grazing angle), no neighbour has a positive pdf: the
// sample of an edge input (which maps onto the support's edges and corners
// by design) is accepted in the same count when samples of inputs
// approaching its input from inside converge to it and one has a positive
// pdf (inward_ladder; figure zero_pdf_below_resolution). Random samples get
// no such excuse: a sampler that overshoots its support continuously would
// earn it too, and its random samples are what catch it. --strict withholds the
// allowance: every such sample fails.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "chi2/count_bounds.h"
#include "sampling/float_bits.h"
#include "validate/api/light_case.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/float_probe.h"
#include "validate/checks/shared/formatting.h"
#include "validate/checks/shared/input_chunks.h"

namespace warpcheck {
namespace {

struct Example {
    WarpInput input;
    WarpOutput output{};
    double pdf = 0.0;
};

struct ConsistencyStats {
    uint64_t count = 0, random_count = 0;
    uint64_t declined = 0;  ///< a light's inputs that gave no sample (pdf 0 returned): skipped
    uint64_t declined_random = 0;  ///< of those, random inputs
    Tally<Example> nan_sample, outside, bad_pdf, zero_pdf;
    uint64_t boundary_zero = 0;
    Tally<Example> boundary_random;  ///< the boundary zeros among random inputs (bounded as rounded_random)
    Tally<Example> rounded_random;  ///< pdf 0 within kProbeUlps of a positive pdf: random inputs
    uint64_t rounded_edges = 0;     ///< the same among the edge inputs
    EdgeBand band;                  ///< random samples with a positive pdf probed for a zero pdf nearby
    /// Of the rounded samples (edge and random), those excused as limits of
    /// samples with a positive pdf (limit_of_support), not by a float neighbour.
    uint64_t below_resolution = 0;
    double min_pdf = std::numeric_limits<double>::infinity();
    double max_pdf = 0.0;

    void merge(const ConsistencyStats& o) {
        count += o.count;
        random_count += o.random_count;
        declined += o.declined;
        declined_random += o.declined_random;
        rounded_random.merge(o.rounded_random);
        rounded_edges += o.rounded_edges;
        band.merge(o.band);
        below_resolution += o.below_resolution;
        nan_sample.merge(o.nan_sample);
        outside.merge(o.outside);
        bad_pdf.merge(o.bad_pdf);
        zero_pdf.merge(o.zero_pdf);
        boundary_zero += o.boundary_zero;
        boundary_random.merge(o.boundary_random);
        min_pdf = std::min(min_pdf, o.min_pdf);
        max_pdf = std::max(max_pdf, o.max_pdf);
    }
};

bool finite_point(const chi2::DomainPoint& p, int dims) {
    for (int k = 0; k < dims; ++k)
        if (!std::isfinite(p[static_cast<std::size_t>(k)])) return false;
    return true;
}

/// Sorts one sample into the kinds of violation (or none); a zero pdf inside
/// the domain and off its boundary is left to the probe (returns true).
bool classify(ConsistencyStats& s, const chi2::Domain& domain, uint64_t index, const Example& e, bool random) {
    ++s.count;
    const chi2::DomainPoint p = to_domain_point(e.output);
    if (!finite_point(p, domain.point_dimension())) {
        s.nan_sample.add(index, e);
        return false;
    }
    const bool inside = domain.contains(p);
    if (!inside) s.outside.add(index, e);
    if (!std::isfinite(e.pdf) || e.pdf < 0.0) {
        s.bad_pdf.add(index, e);
    } else if (e.pdf == 0.0) {
        if (domain.on_boundary(p)) {
            ++s.boundary_zero;
            if (random) s.boundary_random.add(index, e);
        } else if (inside) {
            return true;
        }
        else s.zero_pdf.add(index, e);
    } else {
        s.min_pdf = std::min(s.min_pdf, e.pdf);
        s.max_pdf = std::max(s.max_pdf, e.pdf);
    }
    return false;
}

/// The pdf at the points x.
std::vector<double> pdf_at(const WarpCase& warp, std::span<const WarpOutput> x) {
    std::vector<double> pdf(x.size());
    warp.pdf(x, pdf);
    return pdf;
}

/// Whether the pdf is positive (and finite) at one of the probed neighbours
/// of each of the samples `which`: one evaluation for all (ProbeBatch).
std::vector<unsigned char> positive_nearby(const WarpCase& warp, std::span<const WarpOutput> x,
                                           std::span<const std::size_t> which) {
    return holds_at_a_probe(
        which, [&](std::size_t i) { return probe_points(warp.domain(), x[i]); },
        [&](std::span<const WarpOutput> points) { return pdf_at(warp, points); },
        [](std::size_t, const std::vector<double>& pdf, std::size_t j) { return pdf[j] > 0.0 && std::isfinite(pdf[j]); });
}

/// Whether x, the sample of `input` with pdf 0 and no positive pdf at its
/// float neighbours, lies on the support's closure below float resolution:
/// the samples of inputs approaching `input` from inside converge to x, and
/// one of them has a positive pdf (float_probe.h, inward_ladder).
bool limit_of_support(const WarpCase& warp, const WarpInput& input, const WarpOutput& x) {
    const std::vector<WarpInput> ladder = inward_ladder(input, warp.input_kind());
    if (ladder.empty() || !warp.has_pdf()) return false;
    std::vector<WarpOutput> xs(ladder.size());
    std::vector<double> pdf(ladder.size());
    if (declines_samples(warp)) {
        warp.sample_with_value(ladder, xs, pdf);
        if (std::any_of(pdf.begin(), pdf.end(), [](double v) { return v == 0.0; })) return false;  // declined
    } else {
        warp.sample(ladder, xs);
    }
    warp.pdf(xs, pdf);
    std::vector<unsigned char> passes(ladder.size());
    for (std::size_t k = 0; k < ladder.size(); ++k) passes[k] = pdf[k] > 0.0 && std::isfinite(pdf[k]);
    return excused_in_the_limit(warp.domain(), x, xs, passes);
}

/// Whether each of the samples `which`, with a positive pdf, lies within
/// kProbeUlps spacings of a zero pdf inside the domain (axis_probes: a zero
/// just beyond the domain's own boundary is not a support's edge; the
/// boundary's zeros are bounded apart, boundary_problem). One evaluation for all.
std::vector<unsigned char> near_support_edge(const WarpCase& warp, std::span<const WarpOutput> x,
                                             std::span<const std::size_t> which) {
    return holds_at_a_probe(
        which, [&](std::size_t i) { return axis_probes(warp.domain(), x[i]); },
        [&](std::span<const WarpOutput> points) { return pdf_at(warp, points); },
        [](std::size_t, const std::vector<double>& pdf, std::size_t j) { return pdf[j] == 0.0; });
}

/// One chunk of samples with their pdfs, classified.
ConsistencyStats classify_chunk(const WarpCase& warp, std::size_t chunk, std::span<const WarpInput> inputs,
                     std::span<const WarpOutput> x, std::span<const double> pdf,
                     std::span<const unsigned char> declined, std::size_t stride) {
    const chi2::Domain& domain = warp.domain();
    ConsistencyStats s;
    if (chunk > 0) s.random_count = inputs.size();
    // The samples probed for a zero pdf nearby and the zero pdfs inside the
    // domain probed for a positive one nearby, each set in one batch (the
    // tallies keep their first example by index, whatever the order).
    std::vector<std::size_t> banded, zero;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        if (!declined.empty() && declined[i]) {
            ++s.declined;
            s.declined_random += chunk > 0 ? 1 : 0;
            continue;
        }
        if (chunk > 0 && warp.has_pdf() && i % stride == 0 && pdf[i] > 0.0 && std::isfinite(pdf[i]) &&
            domain.contains(to_domain_point(x[i])))
            banded.push_back(i);
        if (classify(s, domain, chunk * kInputChunkSize + i, {inputs[i], x[i], pdf[i]}, chunk > 0)) zero.push_back(i);
    }
    for (const unsigned char near : near_support_edge(warp, x, banded)) s.band.add(near != 0);
    // A zero pdf inside the domain: rounded across the support's edge, or a violation.
    const std::vector<unsigned char> rounded =
        warp.has_pdf() ? positive_nearby(warp, x, zero) : std::vector<unsigned char>(zero.size(), 0);
    for (std::size_t k = 0; k < zero.size(); ++k) {
        const std::size_t i = zero[k];
        const uint64_t index = chunk * kInputChunkSize + i;
        const Example e{inputs[i], x[i], pdf[i]};
        const bool limit = chunk == 0 && !rounded[k] && warp.has_pdf() && limit_of_support(warp, inputs[i], x[i]);
        if (!rounded[k] && !limit) s.zero_pdf.add(index, e);
        else if (chunk == 0) ++s.rounded_edges;
        else s.rounded_random.add(index, e);
        s.below_resolution += limit ? 1 : 0;
    }
    return s;
}

ConsistencyStats compute(const WarpCase& warp, const CheckContext& ctx) {
    auto parts = map_input_chunks<ConsistencyStats>(ctx, warp.input_kind(), ctx.options().samples, true,
                                         [&](std::size_t chunk, std::span<const WarpInput> inputs) {
        std::vector<WarpOutput> x(inputs.size());
        std::vector<double> pdf(inputs.size());
        std::vector<unsigned char> declined;
        if (declines_samples(warp)) {
            // A light (or an MIS case's strategy) may decline to sample (pbrt's SampleLi returns none:
            // pdf 0): not a sample, so not judged here; light_irradiance
            // counts it as the zero it contributes.
            warp.sample_with_value(inputs, x, pdf);
            declined.resize(inputs.size());
            for (std::size_t i = 0; i < inputs.size(); ++i) declined[i] = pdf[i] == 0.0;
            warp.pdf(x, pdf);
        } else if (warp.has_pdf()) {
            warp.sample(inputs, x);
            warp.pdf(x, pdf);
        } else {
            warp.sample_with_value(inputs, x, pdf);  // the pdf that sample returns
        }
        return classify_chunk(warp, chunk, inputs, x, pdf, declined, edge_band_stride(ctx.options().samples));
    });
    return merge_in_order(parts);
}

/// How many random samples may lie on the domain's boundary with pdf 0: a
/// Poisson bound at kRoundedAcrossEdgeRate (the boundary has no measure).
uint64_t boundary_bound(const ConsistencyStats& s) {
    return chi2::poisson_count_bound(static_cast<double>(s.random_count) * kRoundedAcrossEdgeRate, kConsistencyBoundTail);
}

/// How many random samples may have pdf 0 next to a positive pdf: a Poisson
/// bound on the larger of kRoundedAcrossEdgeRate and the measured share of
/// samples that lie within the probe's reach of a support edge (only those
/// can round across it).
uint64_t rounded_bound(const ConsistencyStats& s) {
    return rounded_across_edge_bound(s.random_count - s.declined_random, s.band);
}

struct Finding {
    const Tally<Example>* tally;
    std::string what;
};

/// The kinds of violation in the order the verdict states them.
std::vector<Finding> findings(const ConsistencyStats& s, const chi2::Domain& domain) {
    return {{&s.nan_sample, "samples with NaN or infinite coordinates"},
            {&s.outside, fmt::format("samples outside the {}", domain.describe())},
            {&s.bad_pdf, "samples with a NaN, infinite or negative pdf"},
            {&s.zero_pdf, "samples with pdf 0 inside the domain"}};
}

/// The rule for zero pdfs next to a positive one (see the top): over the
/// bound, or any under --strict, fails. Empty when it passes.
/// Random samples on the boundary with pdf 0: the boundary has no measure, so
/// a correct warp lands there (with the density's zero) only by rounding from
/// within a few float spacings of it, the band kRoundedAcrossEdgeRate bounds;
/// a warp that clamps onto its rim where its pdf is 0 (a tiny cap sampled a
/// few floats too wide) puts a fixed fraction there, and each such sample has
/// an infinite weight f / pdf. Edge inputs (u.x = 0 onto z = 0) are apart.
std::string boundary_problem(const ConsistencyStats& s, InputKind kind, int dims) {
    const uint64_t bound = boundary_bound(s);
    if (s.boundary_random.count <= bound) return {};
    std::string text = fmt::format("{} of {} random samples lie on the domain's boundary with pdf 0, more than the {} "
                                   "that float rounding onto it explains: the warp puts mass where its pdf is 0",
                                   s.boundary_random.count, s.random_count, bound);
    const Example& e = *s.boundary_random.first;
    text += fmt::format(" (e.g. u = {} -> x = {})", format_input(e.input, kind), format_output(e.output, dims));
    return text;
}

std::string rounded_problem(const ConsistencyStats& s, bool strict, InputKind kind, int dims) {
    const uint64_t all = s.rounded_random.count + s.rounded_edges, bound = rounded_bound(s);
    if (all == 0 || (!strict && s.rounded_random.count <= bound)) return {};
    std::string text =
        strict ? fmt::format("{} samples with pdf 0 within {} float spacings of a positive pdf (float rounding at "
                             "the edge of the support; --strict withholds this allowance)",
                             all, kProbeUlps)
               : fmt::format("{} of {} random samples have pdf 0 within {} float spacings of a positive pdf, more "
                             "than the {} that float rounding at the edge of the support explains: the warp puts "
                             "mass on the edge where its pdf is 0",
                             s.rounded_random.count, s.random_count, kProbeUlps, bound);
    if (s.rounded_random.first) {
        const Example& e = *s.rounded_random.first;
        text += fmt::format(" (e.g. u = {} -> x = {})", format_input(e.input, kind), format_output(e.output, dims));
    }
    return text;
}

/// The verdict: any sample of any kind of violation fails; there is no
/// tolerance on counts, since a correct warp produces none, except for the
/// zero pdfs that float rounding at the support's edge explains (bounded).
void judge_and_explain(CheckResult& r, const ConsistencyStats& s, const WarpCase& warp, bool strict) {
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
    if (std::string rounded = rounded_problem(s, strict, kind, dims); !rounded.empty())
        problems.push_back(std::move(rounded));
    if (std::string boundary = boundary_problem(s, kind, dims); !boundary.empty())
        problems.push_back(std::move(boundary));
    r.verdict = problems.empty() ? Verdict::Pass : Verdict::Fail;
    if (problems.empty()) {
        r.summary = fmt::format("pdf in [{:.3g}, {:.3g}]", s.min_pdf, s.max_pdf);
        if (s.boundary_zero > 0) r.summary += fmt::format(", {} zero on boundary", s.boundary_zero);
        const uint64_t rounded = s.rounded_random.count + s.rounded_edges;
        if (rounded > 0) r.summary += fmt::format(", {} zero at the support's edge (float rounding)", rounded);
        return;
    }
    r.summary = problems.front().substr(0, problems.front().find(" (e.g."));
    r.message = join_reasons(problems);
    if (!examples.rows.empty()) r.tables.push_back(std::move(examples));
}

/// Under --strict (figure "strict"), no sample may have pdf 0 beside a positive pdf.
void strict_rounding_line(const CheckResult& r, std::vector<JudgedQuantity>& out) {
    if (r.figure("strict").value_or(0.0) == 0.0) return;
    const double all = r.figure("zero_pdf_rounded_random").value_or(0.0) + r.figure("zero_pdf_rounded_edge_inputs").value_or(0.0);
    out.push_back({"samples with pdf 0 beside a positive pdf (--strict allows none)", judged_number(all), "= 0",
                   all == 0.0 ? JudgedQuantity::State::Within : JudgedQuantity::State::Beyond});
}

void add_figures(CheckResult& r, const ConsistencyStats& s) {
    r.samples = s.count;
    r.figures = {{"samples", static_cast<double>(s.count)},
                 {"non_finite_samples", static_cast<double>(s.nan_sample.count)},
                 {"declined_samples", static_cast<double>(s.declined)},
                 {"outside_domain", static_cast<double>(s.outside.count)},
                 {"non_finite_or_negative_pdf", static_cast<double>(s.bad_pdf.count)},
                 {"zero_pdf", static_cast<double>(s.zero_pdf.count)},
                 {"zero_pdf_on_boundary", static_cast<double>(s.boundary_zero)},
                 {"zero_pdf_on_boundary_random", static_cast<double>(s.boundary_random.count)},
                 {"zero_pdf_on_boundary_bound", static_cast<double>(boundary_bound(s))},
                 {"min_pdf", s.min_pdf},
                 {"max_pdf", s.max_pdf},
                 {"zero_pdf_rounded_random", static_cast<double>(s.rounded_random.count)},
                 {"zero_pdf_rounded_edge_inputs", static_cast<double>(s.rounded_edges)},
                 {"zero_pdf_rounded_bound", static_cast<double>(rounded_bound(s))},
                 {"edge_band_probed", static_cast<double>(s.band.probed)},
                 {"edge_band_near_edge", static_cast<double>(s.band.near)},
                 {"zero_pdf_below_resolution", static_cast<double>(s.below_resolution)}};
}

class ConsistencyCheck final : public Check {
public:
    std::string name() const override { return "consistency"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"non_finite_samples", "samples with NaN or infinite coordinates", FigureRule::Zero},
                 {"outside_domain", "samples outside the domain", FigureRule::Zero},
                 {"non_finite_or_negative_pdf", "samples with a NaN, infinite or negative pdf", FigureRule::Zero},
                 {"zero_pdf", "samples with pdf 0 inside the domain", FigureRule::Zero},
                 {"zero_pdf_on_boundary", "samples with pdf 0 on the boundary", FigureRule::Counted},
                 {"zero_pdf_on_boundary_random", "of them, random samples (float rounding onto the boundary)",
                  FigureRule::AtMost, "zero_pdf_on_boundary_bound"},
                 {"zero_pdf_rounded_random", "random samples with pdf 0 beside a positive pdf (float rounding)", FigureRule::AtMost, "zero_pdf_rounded_bound"},
                 {"zero_pdf_rounded_edge_inputs", "edge inputs with pdf 0 beside a positive pdf", FigureRule::Counted}},
                .bounds = strict_rounding_line};
    }
    CheckLegend legend() const override {
        return {name(), "Every sample lies in the domain and has a finite, positive pdf: counts must be 0, but for a "
                "pdf of 0 on the boundary, and one beside a positive pdf (float rounding at a support's edge) within "
                "its Poisson bound.",
                ""};
    }
    std::string description() const override {
        return "every sample lies in the domain and has a finite, positive pdf (edge inputs included)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        return Applicability::when(!warp.is_discrete());
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const ConsistencyStats stats = compute(warp, ctx);
        if (stats.count == 0 && stats.declined > 0) return nothing_sampled(stats.declined);
        CheckResult r;
        add_figures(r, stats);
        if (ctx.options().strict) r.figures.push_back({"strict", 1.0});  // the rounding allowance withheld
        judge_and_explain(r, stats, warp, ctx.options().strict);
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_consistency_check() { return std::make_unique<ConsistencyCheck>(); }

}  // namespace warpcheck
