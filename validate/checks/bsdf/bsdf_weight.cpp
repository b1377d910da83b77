// "bsdf_weight": what every sample claims, against the BSDF's own functions at
// its wi (edge inputs included). A renderer multiplies its path throughput by
// the sample's weight f |cos theta_i| / pdf, computed along the sampler's path
// (often from the sampled microfacet normal, before wi exists), while MIS and
// light sampling use f() and pdf() recomputed from wi: where the two disagree,
// the image is biased even if every wi lands where it should. Rules, each a
// FAIL by itself (none can fail a correct sampler by chance):
//  - wi is a unit vector (within kUnitTolerance) on the side its flags say
//    (reflection: wo's side; transmission: the other; a phase function: any);
//  - a continuous sample lands where pdf(wo, wi) > 0 and f(wo, wi) > 0, and
//    (or it returns f = 0 where f(wo, wi) = 0 too: a zero-weight sample, which
//    claims nothing and is counted, zero_weight_samples) its weight equals f(wo, wi) |cos theta_i| / pdf(wo, wi) within
//    kRelativeTolerance; or, where f() and pdf() recomputed from the rounded
//    wi are at their float resolution (a refraction through a microfacet seen
//    edge-on, whose half vector's side is a matter of rounding), within the
//    range of the weights recomputed at wi's float neighbours (bsdf_common.h)
//    widened by that range and by kRelativeTolerance: such samples are
//    excused, counted (those from random inputs, and those where f() or pdf()
//    at wi is 0, apart) and their largest disagreement reported (excused,
//    excused_random, excused_outside_support, excused_max_relative); more than
//    kExcusedRandomShare of the random inputs' samples excused is a FAIL;
//  - a delta sample's weight is finite and positive, and its pdf (the
//    probability of its lobe) at most 1;
//  - a continuous transmission reports the eta the case claims, eta(wi) /
//    eta(wo) within kEtaTolerance (bsdf_common.h; bsdf_delta holds delta
//    transmissions to the same): a renderer scales its path by 1 / eta^2 and
//    tracks the medium from it, so a wrong one biases the image where the
//    direction and weight are right.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "validate/checks/bsdf/bsdf_checks.h"
#include "validate/checks/bsdf/bsdf_common.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/formatting.h"

namespace warpcheck::bsdf {
namespace {

/// Largest relative disagreement of the two weights: float_probe.h says why
/// (bsdf_common.h includes it).
constexpr double kRelativeTolerance = kReturnedValueTolerance;
/// How far |wi| may be from 1: 2^-18 (32 float roundings of 2^-23): a direction
/// normalised and then carried through a reflection, a refraction or a frame
/// change in float; one never normalised, or built with a wrong sine, is off by percent.
constexpr double kUnitTolerance = 0x1p-18;

/// The largest share of the random inputs' continuous samples that the float
/// resolution rule may excuse, 2^-10: a correct float sampler's random samples
/// are at float resolution only within ~kFloatStep (2^-20 rad) of where f or
/// pdf changes abruptly (a support's edge, a critical angle), a band whose
/// probability is the band's width times its length times the density there,
/// ~2^-20 x 2 pi x a density of at most tens per steradian at such an edge
/// (the built-ins excuse none of 2 10^7 random samples: their excused are all
/// edge inputs); more means f() or pdf() disagree with the sampler on a set a
/// renderer hits (zero on 1/256 of the directions, say), which the excuse
/// must not hide.
constexpr double kExcusedRandomShare = 0x1p-10;

enum Kind { kNotUnit, kWrongSide, kZeroPdf, kZeroF, kWeight, kDeltaWeight, kWrongEta, kExcusedMany, kKinds };
const char* const kKindFigure[kKinds] = {"not_unit",  "wrong_side", "zero_pdf",  "zero_f", "weight_mismatches",
                                         "bad_delta", "wrong_eta",  "excused_random"};
const char* const kKindText[kKinds] = {
    "wi is not a unit vector",
    "wi is on the wrong side for its flags",
    "a continuous sample lands where pdf(wo, wi) is 0",
    "a continuous sample lands where f(wo, wi) is 0",
    "the weight differs from f(wo, wi) |cos theta_i| / pdf(wo, wi)",
    "a delta sample's weight is not finite and positive, or its probability exceeds 1",
    "a continuous transmission's eta is not the claimed eta(wi) / eta(wo)",
    "more random inputs' samples at float resolution than a sharp edge of f or pdf can hold (f() or pdf() "
    "disagrees with the sampler on a set of directions, not at an edge)",
};

struct Example {
    WarpInput input;
    BsdfRecord record;
    double weight = 0.0, f_at = 0.0, pdf_at = 0.0, weight_at = 0.0;
};

struct Stats {
    uint64_t samples = 0, sampled = 0, delta = 0, excused = 0;
    /// The continuous samples of the random inputs (the edge inputs' are the
    /// others); of the excused, those where f() or pdf() recomputed at wi is 0
    /// (the excused from random inputs are kinds[kExcusedMany]).
    uint64_t continuous_random = 0, excused_outside = 0, zero_weight = 0;
    double max_relative = 0.0, max_unit_error = 0.0, excused_max_relative = 0.0;
    std::array<Tally<Example>, kKinds> kinds{};
    WorstK<Example> worst{10};
    void merge(const Stats& o) {
        samples += o.samples;
        sampled += o.sampled;
        delta += o.delta;
        excused += o.excused;
        continuous_random += o.continuous_random;
        excused_outside += o.excused_outside;
        zero_weight += o.zero_weight;
        excused_max_relative = max_nan_wins(excused_max_relative, o.excused_max_relative);
        max_relative = max_nan_wins(max_relative, o.max_relative);
        max_unit_error = max_nan_wins(max_unit_error, o.max_unit_error);
        for (int k = 0; k < kKinds; ++k) kinds[static_cast<std::size_t>(k)].merge(o.kinds[static_cast<std::size_t>(k)]);
        worst.merge(o.worst);
    }
};

/// The side rule: whether wi lies where the sample's flags put it.
bool on_its_side(const BsdfCase& bsdf, const BsdfRecord& r) {
    if (bsdf.phase_function()) return true;
    const float side = r.wi[2] * bsdf.wo().z;
    return has(r.flags, BsdfFlags::Transmission) ? side < 0.0f : side > 0.0f;
}

/// Whether each example's returned weight lies within the range of the
/// weights that f() and pdf() give at its wi and its float neighbours,
/// widened by that range. One evaluation of f and pdf for all (ProbeBatch).
std::vector<unsigned char> within_float_resolution(const BsdfCase& bsdf, std::span<const Example> examples) {
    ProbeBatch probes;
    for (const Example& e : examples) probes.add(float_neighbours(e.record.wi));
    const std::vector<WarpOutput> wo(probes.points.size(), detail::to_output_of(bsdf.wo()));
    std::vector<double> f(probes.points.size()), pdf(probes.points.size());
    if (!probes.points.empty()) {
        bsdf.f(wo, probes.points, f);
        bsdf.pdf(probes.points, pdf);
    }
    std::vector<unsigned char> out(examples.size());
    for (std::size_t k = 0; k < examples.size(); ++k) {
        const Example& e = examples[k];
        double lo = HUGE_VAL, hi = -HUGE_VAL;
        const auto include = [&](double w) {
            if (!std::isfinite(w)) return;
            lo = std::min(lo, w);
            hi = std::max(hi, w);
        };
        include(e.weight_at);
        for (std::size_t j = probes.start[k]; j < probes.start[k + 1]; ++j)
            if (pdf[j] > 0.0) include(f[j] * bsdf.cosine(probes.points[j]) / pdf[j]);
        // The neighbours stand in for wi, so the weight is held to them as to wi
        // itself: within kRelativeTolerance of their range, widened by the range's
        // spread (where the neighbours agree to the last bits, the spread alone
        // would ask for an identity that two float paths do not give).
        const double width = hi - lo + kRelativeTolerance * std::max(std::abs(lo), std::abs(hi));
        out[k] = lo <= hi && e.weight >= lo - width && e.weight <= hi + width;
    }
    return out;
}

/// |wi| in double: the squares of float components are exact in double and
/// their sum is off by 2^-53 relative, far below kUnitTolerance (and a third
/// of the cost of std::hypot, which guards against overflow that three floats
/// cannot reach in double).
double length(const WarpOutput& w) {
    const double x = w[0], y = w[1], z = w[2];
    return std::sqrt(x * x + y * y + z * z);
}

/// The rules every sample answers to: unit length, its side; for a delta
/// sample a finite positive weight of probability at most 1, for a continuous
/// transmission the claimed eta.
void judge_direction(const BsdfCase& bsdf, Stats& s, uint64_t index, const Example& e) {
    const BsdfRecord& r = e.record;
    const double len = length(r.wi);
    s.max_unit_error = max_nan_wins(s.max_unit_error, std::abs(len - 1.0));
    if (!(std::abs(len - 1.0) <= kUnitTolerance)) s.kinds[kNotUnit].add(index, e);
    if (!on_its_side(bsdf, r)) s.kinds[kWrongSide].add(index, e);
    if (r.delta() && !(e.weight > 0.0 && std::isfinite(e.weight) && r.pdf <= 1.0f)) s.kinds[kDeltaWeight].add(index, e);
    const bool continuous_transmission = !bsdf.phase_function() && !r.delta() && has(r.flags, BsdfFlags::Transmission);
    if (continuous_transmission && !(std::abs(r.eta / claimed_eta(bsdf) - 1.0) <= kEtaTolerance))
        s.kinds[kWrongEta].add(index, e);
}

/// A sample of weight 0 where f() is 0 too (a black Lambertian, a lobe of
/// weight 0) claims nothing and adds nothing: the identity 0 = 0 |cos| / pdf
/// holds exactly, so it agrees (counted as zero_weight); a sample whose f
/// is positive where f() is 0 is the failure the rule is for.
bool zero_weight(const Example& e) { return e.pdf_at > 0.0 && e.record.f == 0.0f && e.f_at == 0.0; }

/// Whether a continuous sample's weight agrees with f(wo, wi) |cos| / pdf(wo, wi) (weight_at set).
bool agrees(const Example& e) {
    return e.pdf_at > 0.0 && e.f_at > 0.0 && relative_difference(e.weight, e.weight_at) <= kRelativeTolerance;
}

/// Judges a continuous sample's weight, given f(wo, wi) and pdf(wo, wi) at
/// its wi (weight_at set) and, where it does not agree, whether it lies within
/// the float resolution of f and pdf around wi.
void judge_weight(Stats& s, uint64_t index, bool edge, const Example& e, bool within_resolution) {
    const double rel = relative_difference(e.weight, e.weight_at);
    if (zero_weight(e)) {
        ++s.zero_weight;
        return;
    }
    if (!agrees(e) && within_resolution) {
        ++s.excused;
        if (!edge) s.kinds[kExcusedMany].add(index, e);
        if (e.pdf_at > 0.0 && e.f_at > 0.0) s.excused_max_relative = max_nan_wins(s.excused_max_relative, rel);
        else ++s.excused_outside;
        return;
    }
    const auto add = [&](Kind k) { s.kinds[k].add(index, e); };
    if (!(e.pdf_at > 0.0)) add(kZeroPdf);
    if (!(e.f_at > 0.0)) add(kZeroF);
    s.max_relative = max_nan_wins(s.max_relative, rel);
    if (!(rel <= kRelativeTolerance)) add(kWeight);
    if (s.worst.wants(rel)) s.worst.offer(rel, index, e);
}

/// What a chunk needs besides its records, kept per thread from chunk to
/// chunk: the continuous samples' wi and their f and pdf there (fresh
/// vectors of a chunk's size each time cost a tenth of the check in page
/// faults alone).
struct Scratch {
    std::vector<std::size_t> continuous;
    std::vector<WarpOutput> wi, wo;
    std::vector<double> f, pdf;
};

Stats judge_chunk(const BsdfCase& bsdf, std::size_t chunk, std::span<const WarpInput> in,
                  std::span<const BsdfRecord> rec) {
    thread_local Scratch t;
    t.continuous.clear();
    t.wi.clear();
    Stats s;
    s.samples = rec.size();
    for (std::size_t i = 0; i < rec.size(); ++i) {
        if (!rec[i].sampled()) continue;
        ++s.sampled;
        const double weight = static_cast<double>(rec[i].f) * bsdf.cosine(rec[i].wi) / rec[i].pdf;
        judge_direction(bsdf, s, chunk * kInputChunkSize + i, Example{in[i], rec[i], weight, 0.0, 0.0, 0.0});
        if (rec[i].delta()) {
            ++s.delta;
        } else {
            t.continuous.push_back(i);
            t.wi.push_back(rec[i].wi);
        }
    }
    // f() and pdf() only where a continuous sample landed: a delta sample's
    // direction has no density to compare with.
    const std::size_t n = t.wi.size();
    t.wo.assign(n, detail::to_output_of(bsdf.wo()));
    t.f.resize(n);
    t.pdf.resize(n);
    bsdf.f(t.wo, t.wi, t.f);
    bsdf.pdf(t.wi, t.pdf);
    // The samples that do not agree are tried at their float neighbours in one batch.
    std::vector<Example> examples(n), disagreeing;
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = t.continuous[k];
        Example& e = examples[k];
        e = Example{in[i], rec[i], static_cast<double>(rec[i].f) * bsdf.cosine(rec[i].wi) / rec[i].pdf, t.f[k],
                    t.pdf[k], 0.0};
        e.weight_at = e.f_at * bsdf.cosine(e.record.wi) / e.pdf_at;
        if (!zero_weight(e) && !agrees(e)) disagreeing.push_back(e);
    }
    const std::vector<unsigned char> within = within_float_resolution(bsdf, disagreeing);
    for (std::size_t k = 0, d = 0; k < n; ++k) {
        const Example& e = examples[k];
        const bool tried = !zero_weight(e) && !agrees(e);
        judge_weight(s, chunk * kInputChunkSize + t.continuous[k], chunk == 0, e, tried && within[d++] != 0);
    }
    if (chunk != 0) s.continuous_random = n;  // chunk 0 holds the edge inputs (map_bsdf_chunks with edges)
    return s;
}

Stats compute(const BsdfCase& bsdf, const CheckContext& ctx) {
    const auto parts = map_bsdf_chunks<Stats>(
        ctx, bsdf, ctx.options().samples, true,
        [&](std::size_t chunk, std::span<const WarpInput> in, std::span<const BsdfRecord> rec) {
            return judge_chunk(bsdf, chunk, in, rec);
        });
    return merge_in_order(parts);
}

std::string describe(const Example& e) {
    return fmt::format("input {}: wi ({:.9g}, {:.9g}, {:.9g}), f {:.9g}, pdf {:.9g}, weight {:.9g}, eta {:.9g}; "
                       "f(wo, wi) {:.9g}, pdf(wo, wi) {:.9g}, their weight {:.9g}",
                       format_input(e.input, InputKind::Uniform3D), e.record.wi[0], e.record.wi[1], e.record.wi[2],
                       e.record.f, e.record.pdf, e.weight, e.record.eta, e.f_at, e.pdf_at, e.weight_at);
}

/// The count of random inputs' excused samples beyond which the row fails.
double excused_random_limit(const Stats& s) {
    return kExcusedRandomShare * static_cast<double>(s.continuous_random);
}

/// Whether kind k fails the row: any sample of it, but the excused, which
/// fail only beyond their limit.
bool fails(const Stats& s, int k) {
    const uint64_t count = s.kinds[static_cast<std::size_t>(k)].count;
    return k == kExcusedMany ? static_cast<double>(count) > excused_random_limit(s) : count > 0;
}

void judge(CheckResult& r, const Stats& s) {
    r.summary = fmt::format("max rel. weight diff {:.3g}, max ||wi| - 1| {:.3g} ({} samples, {} delta, {} at float "
                            "resolution, {} of them from random inputs)",
                            s.max_relative, s.max_unit_error, s.sampled, s.delta, s.excused, s.kinds[kExcusedMany].count);
    std::vector<std::string> reasons;
    int first = -1;
    for (int k = 0; k < kKinds; ++k) {
        if (!fails(s, k)) continue;
        const Tally<Example>& t = s.kinds[static_cast<std::size_t>(k)];
        if (first < 0) first = k;
        const std::string limit =
            k == kExcusedMany ? fmt::format(", more than {:.0f}", excused_random_limit(s)) : std::string();
        reasons.push_back(fmt::format("{} at {} of {} samples{} (first: {})", kKindText[k], t.count, s.sampled, limit,
                                      describe(*t.first)));
    }
    r.verdict = reasons.empty() ? Verdict::Pass : Verdict::Fail;
    if (reasons.empty()) return;
    r.summary = fmt::format("{} at {} of {} samples", kKindText[first], s.kinds[static_cast<std::size_t>(first)].count,
                            s.sampled);
    r.message = join_reasons(reasons);
}

Table worst_table(const Stats& s) {
    Table t{"Largest weight disagreements (continuous samples)",
            {"input (uc, u.x, u.y)", "wi", "f", "pdf", "weight", "f(wo, wi)", "pdf(wo, wi)", "their weight",
             "relative difference"},
            {}};
    for (const auto& entry : s.worst.entries()) {
        const Example& e = entry.item;
        t.rows.push_back({format_input(e.input, InputKind::Uniform3D), format_output(e.record.wi, 3),
                          fmt::format("{:.9g}", e.record.f), fmt::format("{:.9g}", e.record.pdf),
                          fmt::format("{:.9g}", e.weight), fmt::format("{:.9g}", e.f_at),
                          fmt::format("{:.9g}", e.pdf_at), fmt::format("{:.9g}", e.weight_at),
                          fmt::format("{:.3g}", entry.key)});
    }
    return t;
}

class BsdfWeightCheck final : public BsdfCheck {
public:
    std::string name() const override { return "bsdf_weight"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"max_relative_difference", "largest relative weight difference, not excused", FigureRule::AtMost, "tolerance"},
                 {"max_unit_error", "largest ||wi| \u2212 1|", FigureRule::AtMost, "unit_tolerance"},
                 {"weight_mismatches", "samples whose weight differs beyond the tolerance", FigureRule::Zero},
                 {"not_unit", "samples whose wi is not a unit vector", FigureRule::Zero},
                 {"wrong_side", "samples on the wrong side for their flags", FigureRule::Zero},
                 {"zero_pdf", "continuous samples where pdf(wo, wi) is 0", FigureRule::Zero},
                 {"zero_f", "continuous samples where f(wo, wi) is 0", FigureRule::Zero},
                 {"bad_delta", "delta samples with a weight not finite and positive", FigureRule::Zero},
                 {"wrong_eta", "continuous transmissions whose eta is not the case's", FigureRule::Zero},
                 {"excused", "samples at the float resolution of f and pdf (excused)", FigureRule::Counted},
                 {"excused_random", "of them, from random inputs", FigureRule::AtMost, "excused_random_limit"},
                 {"excused_outside_support", "of them, where f or pdf at wi is 0 (a neighbour's is not)", FigureRule::Counted}}};
    }
    CheckLegend legend() const override {
        return {name(), "Every sample's weight f |cos| / pdf against f() and pdf() at its wi (2^-12 relative; "
                "samples at f's and pdf's float resolution excused, counted, and at most 2^-10 of the random "
                "inputs'); wi a unit vector on its flags' side; no sample where pdf or f is 0.",
                ""};
    }
    std::string description() const override {
        return "BSDF: every sample's weight f |cos| / pdf against f() and pdf() at its wi; wi a unit vector on "
               "its flags' side; none where pdf or f is 0; a transmission's eta as claimed (float-rounding tolerance)";
    }

protected:
    Applicability bsdf_applicability(const BsdfCase& b) const override {
        return unless_stochastic(b, "a sample's weight and f() |cos| / pdf() at its wi");
    }

    CheckResult run_bsdf(const BsdfCase& bsdf, const CheckContext& ctx) const override {
        const Stats s = compute(bsdf, ctx);
        CheckResult r;
        r.samples = s.samples;
        r.figures = {{"samples", static_cast<double>(s.samples)},
                     {"sampled", static_cast<double>(s.sampled)},
                     {"delta_samples", static_cast<double>(s.delta)},
                     {"max_relative_difference", s.max_relative},
                     {"tolerance", kRelativeTolerance},
                     {"max_unit_error", s.max_unit_error},
                     {"excused", static_cast<double>(s.excused)},
                     {"excused_max_relative", s.excused_max_relative},
                     {"continuous_random", static_cast<double>(s.continuous_random)},
                     {"excused_random_limit", excused_random_limit(s)},
                     {"excused_outside_support", static_cast<double>(s.excused_outside)},
                     {"zero_weight_samples", static_cast<double>(s.zero_weight)},
                     {"unit_tolerance", kUnitTolerance},
                     {"eta_tolerance", kEtaTolerance}};
        for (int k = 0; k < kKinds; ++k)
            r.figures.push_back({kKindFigure[k], static_cast<double>(s.kinds[static_cast<std::size_t>(k)].count)});
        judge(r, s);
        r.tables.push_back(worst_table(s));
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_bsdf_weight_check() { return std::make_unique<BsdfWeightCheck>(); }

}  // namespace warpcheck::bsdf
