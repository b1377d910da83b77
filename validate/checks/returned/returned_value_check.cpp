// "sample_pdf" and "weight": what a sampler returns with each sample, against
// its functions at that sample. A renderer's Sample(u, &pdf) computes the pdf
// along its own path (often from u, before x exists) while pdf(x) recomputes
// it from x; a BSDF sampler's weight is its own eval / pdf. Where the two
// disagree, a renderer's estimator is biased even when every sample lands
// where it should, so every sample (edge inputs included) is compared:
//   sample_pdf: the returned pdf against pdf(x);
//   weight:     the returned weight against eval(x) / pdf(x).
// A sample that float rounding put across a discontinuity of the functions
// (a light's silhouette, where pdf(x) along the rounded direction misses it; a
// pixel's border) is excused where they agree with the returned value at one
// of x's float neighbours (float_probe.h, the rule consistency uses for a
// zero pdf at a support's edge): edge inputs, which map onto such edges by
// design, are counted; random ones are bounded as consistency bounds them:
// by the fixed rate, or by the measured share of samples whose reference
// jumps (by more than 2^-6, kJumpTolerance: a jump, not the value's float
// noise) within kProbeUlps spacings (EdgeBand), where that is larger (a
// light of angular radius 1e-4 has a few thousandths of its samples there).
// Where the reference is not resolved in float at all (a light's corner seen
// at a grazing angle), an edge input's sample is excused in the same count
// when samples of inputs approaching its input from inside converge to it
// and agree with the reference and with its returned value (figure
// agree_below_resolution); random samples get no such excuse (consistency
// says why).
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "validate/api/light_case.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/float_probe.h"
#include "validate/checks/shared/formatting.h"
#include "validate/checks/shared/input_chunks.h"

namespace warpcheck {
namespace {

/// Largest relative disagreement accepted: float_probe.h says why.
constexpr double kRelativeTolerance = kReturnedValueTolerance;

/// |a - b| / max(|a|, |b|); 0 where they agree to within FLT_MIN; NaN if either is NaN.
double relative_difference(double returned, double reference) {
    const double diff = std::abs(returned - reference);
    if (diff <= FLT_MIN) return 0.0;
    return diff / std::max(std::abs(returned), std::abs(reference));
}

struct Example {
    WarpInput input;
    WarpOutput output{};
    double returned = 0.0;
    double reference = 0.0;
    double eval = 0.0, pdf = 0.0;  // the reference's parts (weight check)
};

struct ReturnedValueStats {
    uint64_t count = 0, mismatches = 0, random_count = 0;
    uint64_t declined = 0;            ///< a light's inputs that gave no sample (returned pdf 0)
    uint64_t declined_random = 0;     ///< of those, random inputs
    uint64_t below_resolution = 0;    ///< of the excused, those excused in the limit (agrees_in_the_limit)
    uint64_t excused_edges = 0;       ///< edge inputs whose value agrees at a float neighbour of x
    Tally<Example> excused_random;    ///< random inputs likewise (bounded)
    EdgeBand band;                    ///< random samples probed for a discontinuity of the reference nearby
    double max_relative = 0.0;
    WorstK<Example> worst{10};

    void merge(const ReturnedValueStats& o) {
        count += o.count;
        declined += o.declined;
        declined_random += o.declined_random;
        below_resolution += o.below_resolution;
        mismatches += o.mismatches;
        random_count += o.random_count;
        excused_edges += o.excused_edges;
        excused_random.merge(o.excused_random);
        band.merge(o.band);
        max_relative = max_nan_wins(max_relative, o.max_relative);
        worst.merge(o.worst);
    }
};

enum class What { Pdf, Weight };

/// The reference of each sample: pdf(x), or eval(x) / pdf(x).
void references(const WarpCase& warp, What what, std::span<const WarpOutput> x, std::vector<Example>& ex) {
    std::vector<double> pdf(x.size()), eval(x.size());
    warp.pdf(x, pdf);
    if (what == What::Weight) warp.eval(x, eval);
    for (std::size_t i = 0; i < x.size(); ++i) {
        ex[i].pdf = pdf[i];
        ex[i].eval = eval[i];
        ex[i].reference = what == What::Pdf ? pdf[i] : eval[i] / pdf[i];
    }
}

/// The references at the points x, returned.
std::vector<Example> references_at(const WarpCase& warp, What what, std::span<const WarpOutput> x) {
    std::vector<Example> ex(x.size());
    references(warp, what, x, ex);
    return ex;
}

/// Whether each of the samples `which` agrees, within the tolerance, with
/// the reference at one of its x's float neighbours (float_probe.h): one
/// evaluation of the references for all.
std::vector<unsigned char> agree_nearby(const WarpCase& warp, What what, std::span<const Example> ex,
                                        std::span<const std::size_t> which) {
    return holds_at_a_probe(
        which, [&](std::size_t i) { return probe_points(warp.domain(), ex[i].output); },
        [&](std::span<const WarpOutput> points) { return references_at(warp, what, points); },
        [&](std::size_t i, const std::vector<Example>& at, std::size_t j) {
            return relative_difference(ex[i].returned, at[j].reference) <= kRelativeTolerance;
        });
}

/// Whether x lies where the reference is not resolved in float (a light's
/// corner seen at a grazing angle), yet the sampler is right there: the
/// samples of inputs approaching e's input from inside converge to x, the
/// nearest one's returned value agrees with e's (the sampler's value is
/// continuous at the input), and further out they agree with the reference
/// (float_probe.h, excused_in_the_limit).
bool agrees_in_the_limit(const WarpCase& warp, What what, const Example& e) {
    const std::vector<WarpInput> ladder = inward_ladder(e.input, warp.input_kind());
    if (ladder.empty()) return false;
    std::vector<WarpOutput> xs(ladder.size());
    std::vector<double> values(ladder.size());
    warp.sample_with_value(ladder, xs, values);
    // The sampler's own value continuous at the input; a declined step (a
    // light's pdf 0) is no sample to converge. Both before the references.
    if (!(relative_difference(e.returned, values[0]) <= kRelativeTolerance)) return false;
    if (declines_samples(warp) && std::any_of(values.begin(), values.end(), [](double v) { return v == 0.0; }))
        return false;
    std::vector<Example> ex(ladder.size());
    references(warp, what, xs, ex);
    std::vector<unsigned char> passes(ladder.size());
    for (std::size_t k = 0; k < ladder.size(); ++k)
        passes[k] = relative_difference(values[k], ex[k].reference) <= kRelativeTolerance;
    return excused_in_the_limit(warp.domain(), e.output, xs, passes);
}

/// Whether the reference at each of the samples `which` jumps
/// (kJumpTolerance) within kProbeUlps spacings along a coordinate
/// (axis_probes): x lies that close to a discontinuity of it (a silhouette, a
/// pixel's border), where rounding can carry a sample across. One evaluation
/// of the references for all.
std::vector<unsigned char> near_discontinuity(const WarpCase& warp, What what, std::span<const Example> ex,
                                              std::span<const std::size_t> which) {
    return holds_at_a_probe(
        which, [&](std::size_t i) { return axis_probes(warp.domain(), ex[i].output); },
        [&](std::span<const WarpOutput> points) { return references_at(warp, what, points); },
        [&](std::size_t i, const std::vector<Example>& at, std::size_t j) {
            return relative_difference(ex[i].reference, at[j].reference) > kJumpTolerance;
        });
}

ReturnedValueStats compute(const WarpCase& warp, const CheckContext& ctx, What what) {
    const bool declines = declines_samples(warp);
    const std::size_t stride = edge_band_stride(ctx.options().samples);
    auto parts = map_input_chunks<ReturnedValueStats>(ctx, warp.input_kind(), ctx.options().samples, true,
                                         [&](std::size_t chunk, std::span<const WarpInput> inputs) {
        std::vector<WarpOutput> x(inputs.size());
        std::vector<double> value(inputs.size());
        warp.sample_with_value(inputs, x, value);
        std::vector<Example> ex(inputs.size());
        references(warp, what, x, ex);
        ReturnedValueStats s;
        if (chunk > 0) s.random_count = inputs.size();
        // The samples probed for a discontinuity nearby and the mismatches
        // tried at their float neighbours, each set probed in one batch.
        std::vector<double> rel(inputs.size());
        std::vector<std::size_t> banded, mismatched;
        for (std::size_t i = 0; i < inputs.size(); ++i) {
            ex[i].input = inputs[i];
            ex[i].output = x[i];
            ex[i].returned = value[i];
            rel[i] = relative_difference(value[i], ex[i].reference);
            if (chunk > 0 && i % stride == 0 && std::isfinite(ex[i].reference)) banded.push_back(i);
            if (!(rel[i] <= kRelativeTolerance) && std::isfinite(value[i])) mismatched.push_back(i);
        }
        const std::vector<unsigned char> near = near_discontinuity(warp, what, ex, banded);
        const std::vector<unsigned char> agrees = agree_nearby(warp, what, ex, mismatched);
        for (std::size_t i = 0, b = 0, m = 0; i < inputs.size(); ++i) {
            ++s.count;
            if (declines && value[i] == 0.0) {
                ++s.declined;
                s.declined_random += chunk > 0 ? 1 : 0;
            }
            if (b < banded.size() && banded[b] == i) s.band.add(near[b++] != 0);
            if (m < mismatched.size() && mismatched[m] == i) {
                const bool nearby = agrees[m++] != 0;
                const bool limit = chunk == 0 && !nearby && agrees_in_the_limit(warp, what, ex[i]);
                if (nearby || limit) {
                    if (chunk == 0) ++s.excused_edges;
                    else s.excused_random.add(chunk * kInputChunkSize + i, ex[i]);
                    s.below_resolution += limit ? 1 : 0;
                    continue;
                }
            }
            s.max_relative = max_nan_wins(s.max_relative, rel[i]);
            if (!(rel[i] <= kRelativeTolerance)) ++s.mismatches;
            if (s.worst.wants(rel[i])) s.worst.offer(rel[i], chunk * kInputChunkSize + i, ex[i]);
        }
        return s;
    });
    return merge_in_order(parts);
}

/// The judge: any sample beyond the tolerance fails (a correct sampler has
/// none), but those whose value agrees at a float neighbour of x; of these,
/// more random ones than rounding puts across an edge fail too.
void judge(CheckResult& r, const ReturnedValueStats& s, What what) {
    const char* value = what == What::Pdf ? "pdf" : "weight";
    const char* reference = what == What::Pdf ? "pdf(x)" : "eval(x) / pdf(x)";
    const uint64_t bound = rounded_across_edge_bound(s.random_count - s.declined_random, s.band);
    const uint64_t excused = s.excused_edges + s.excused_random.count;
    r.summary = fmt::format("max rel. diff {:.3g}", s.max_relative);
    if (excused > 0) r.summary += fmt::format(", {} agree a float step away", excused);
    if (s.mismatches == 0 && s.excused_random.count <= bound) {
        r.verdict = Verdict::Pass;
        if (excused > 0)
            r.message = fmt::format("{} samples ({} of them edge inputs) return a {} that {} gives only at a float "
                                    "neighbour of x: rounded across a discontinuity (at most {} random ones allowed)",
                                    excused, s.excused_edges, value, reference, bound);
        return;
    }
    r.verdict = Verdict::Fail;
    if (s.mismatches == 0) {
        const Example& e = *s.excused_random.first;
        r.summary = fmt::format("{} random samples agree with {} only a float step away", s.excused_random.count,
                                reference);
        r.message = fmt::format("{} random samples return a {} that {} gives only at a float neighbour of x, more "
                                "than the {} float rounding puts across a discontinuity: the {} is wrong along an "
                                "edge (first: returned {:.9g}, {} = {:.9g})", s.excused_random.count, value,
                                reference, bound, value, e.returned, reference, e.reference);
        return;
    }
    const Example& e = s.worst.front().item;
    r.summary = fmt::format("returned {} differs from {} at {} of {} samples", value, reference, s.mismatches, s.count);
    r.message = fmt::format("{} of {} samples return a {} that differs from {} by more than {:.3g} relative; "
                            "worst: returned {:.9g}, {} = {:.9g} (relative difference {:.3g})",
                            s.mismatches, s.count, value, reference, kRelativeTolerance, e.returned, reference,
                            e.reference, s.max_relative);
}

Table worst_table(const ReturnedValueStats& s, const WarpCase& warp, What what) {
    const int dims = warp.domain().point_dimension();
    Table t{"Largest disagreements", {"input u", "sample(u)", "returned", "", "relative difference"}, {}};
    t.columns[3] = what == What::Pdf ? "pdf(x)" : "eval(x) / pdf(x)";
    if (what == What::Weight) t.columns.insert(t.columns.end(), {"eval(x)", "pdf(x)"});
    for (const auto& entry : s.worst.entries()) {
        const Example& e = entry.item;
        std::vector<std::string> row = {format_input(e.input, warp.input_kind()), format_output(e.output, dims),
                                        fmt::format("{:.9g}", e.returned), fmt::format("{:.9g}", e.reference),
                                        fmt::format("{:.3g}", entry.key)};
        if (what == What::Weight) row.insert(row.end(), {fmt::format("{:.9g}", e.eval), fmt::format("{:.9g}", e.pdf)});
        t.rows.push_back(std::move(row));
    }
    return t;
}

class ReturnedValueCheck final : public Check {
public:
    explicit ReturnedValueCheck(What what) : what_(what) {}
    std::string name() const override { return what_ == What::Pdf ? "sample_pdf" : "weight"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"max_relative_difference", "largest relative difference", FigureRule::AtMost, "tolerance"},
                 {"mismatches", "samples beyond the tolerance", FigureRule::Zero}}};
    }
    CheckLegend legend() const override {
        if (name() == "sample_pdf")
            return {name(), "The pdf that sample returns against pdf(x), within float rounding.",
                    ""};
        return {name(), "The weight that sample returns against eval(x) / pdf(x), within float rounding.",
                ""};
    }
    std::string description() const override {
        return what_ == What::Pdf ? "the pdf that sample returns equals pdf(x) at every sample (float-rounding tolerance)"
                                  : "the weight that sample returns equals eval(x) / pdf(x) at every sample "
                                    "(float-rounding tolerance)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        if (what_ == What::Pdf)
            return Applicability::when(warp.sample_returns() == SampleReturns::PointAndPdf && warp.has_pdf());
        return Applicability::when(warp.sample_returns() == SampleReturns::PointAndWeight);
    }

    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const ReturnedValueStats s = compute(warp, ctx, what_);
        if (s.count > 0 && s.declined == s.count) return nothing_sampled(s.count);
        CheckResult r;
        r.samples = s.count;
        r.figures = {{"samples", static_cast<double>(s.count)},
                     {"mismatches", static_cast<double>(s.mismatches)},
                     {"max_relative_difference", s.max_relative},
                     {"agree_at_neighbour_edge_inputs", static_cast<double>(s.excused_edges)},
                     {"agree_at_neighbour_random", static_cast<double>(s.excused_random.count)},
                     {"agree_at_neighbour_bound", static_cast<double>(rounded_across_edge_bound(s.random_count - s.declined_random, s.band))},
                     {"edge_band_probed", static_cast<double>(s.band.probed)},
                     {"edge_band_near", static_cast<double>(s.band.near)},
                     {"agree_below_resolution", static_cast<double>(s.below_resolution)},
                     {"tolerance", kRelativeTolerance}};
        judge(r, s, what_);
        r.tables.push_back(worst_table(s, warp, what_));
        return r;
    }

private:
    What what_;
};

}  // namespace

std::unique_ptr<Check> make_sample_pdf_check() { return std::make_unique<ReturnedValueCheck>(What::Pdf); }
std::unique_ptr<Check> make_weight_check() { return std::make_unique<ReturnedValueCheck>(What::Weight); }

}  // namespace warpcheck
