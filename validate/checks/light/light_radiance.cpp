// "light_radiance": what a light sample returns against the light's own
// intersection. Every sample (edge inputs included) must return a finite L
// equal to L(ref, wi) within kRelativeTolerance, and L(ref, wi) > 0: a sample
// whose direction misses the light (an area-to-solid-angle conversion that
// aimed at the wrong point, a cone wider than the sphere) fails. Not
// statistical: one violation is a failure, except the one class that float
// rounding makes (below), which is bounded and reported.
//
// A direction sampled at the light's silhouette is rounded to float and its
// ray may then graze past the light. Such a miss is excused when the light's
// own L at one of wi's float neighbours (float_probe.h, the rule consistency
// and sample_pdf use) equals the returned L: edge inputs, which the sampler
// maps onto the silhouette by design, are counted; random ones are bounded
// as consistency bounds samples rounded across a support's edge (the fixed
// rate, or the measured share of samples within kProbeUlps of the
// silhouette, EdgeBand, for a light a thousandth of a radian across), while
// a sampler that aims past the light misses far more often. Where the light
// is thinner than a float direction (its corner seen at a grazing angle), an
// edge input's miss is excused in the same count when samples of inputs
// approaching its input from inside converge to it and find the light
// (figure agree_below_resolution; random samples get no such excuse,
// consistency says why).
// Samples below the reference surface and samples that carry no light (L = 0,
// the back of a one-sided emitter) are counted and named in the row, not
// failed: a light sampler does not know the surface, and a dark sample is
// waste, not bias.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "validate/api/light_case.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/float_probe.h"
#include "validate/checks/shared/formatting.h"
#include "validate/checks/shared/input_chunks.h"
#include "validate/checks/light/light_checks.h"

namespace warpcheck::light {
namespace {

/// Largest relative disagreement of the returned L with L(ref, wi), 2^-12
/// (the "weight" check's tolerance): both are the light's radiance, computed
/// along two float paths (a texture lookup from the sampled point, and again
/// from the rounded direction), while a wrong factor is off by percent.
/// How far the returned L may be from L(ref, wi): float_probe.h says why.
constexpr double kRelativeTolerance = kReturnedValueTolerance;

struct Example {
    WarpInput input;
    LightRecord record;
    double reference = 0.0;
};

struct RadianceStats {
    uint64_t count = 0, random_count = 0, no_sample = 0, behind_surface = 0, dark = 0, excused_edges = 0;
    Tally<Example> misses, mismatches, invalid, excused_random;
    EdgeBand band;  ///< random samples probed for a change of L nearby (a silhouette within kProbeUlps)
    uint64_t below_resolution = 0;  ///< of the excused, those excused in the limit (agrees_in_the_limit)
    uint64_t no_sample_random = 0;  ///< random inputs that gave no sample
    double max_relative = 0.0;

    void merge(const RadianceStats& o) {
        count += o.count;
        no_sample += o.no_sample;
        behind_surface += o.behind_surface;
        dark += o.dark;
        random_count += o.random_count;
        excused_edges += o.excused_edges;
        excused_random.merge(o.excused_random);
        band.merge(o.band);
        below_resolution += o.below_resolution;
        no_sample_random += o.no_sample_random;
        misses.merge(o.misses);
        mismatches.merge(o.mismatches);
        invalid.merge(o.invalid);
        max_relative = max_nan_wins(max_relative, o.max_relative);
    }
};

/// The light's own L at the directions wi.
std::vector<double> radiance_at(const LightCase& light, std::span<const WarpOutput> wi) {
    std::vector<double> L(wi.size());
    light.radiance(wi, L);
    return L;
}

/// Whether the light's L at a float neighbour of each of the samples
/// `which` equals its returned L (kRelativeTolerance): wi was rounded across
/// its silhouette or a border. One evaluation of L for all (ProbeBatch).
std::vector<unsigned char> agree_nearby(const LightCase& light, std::span<const LightRecord> rec,
                                        std::span<const std::size_t> which) {
    return holds_at_a_probe(
        which, [&](std::size_t i) { return probe_points(light.domain(), rec[i].wi); },
        [&](std::span<const WarpOutput> points) { return radiance_at(light, points); },
        [&](std::size_t i, const std::vector<double>& L, std::size_t j) {
            const auto returned = static_cast<double>(rec[i].L);
            return std::abs(L[j] - returned) <= kRelativeTolerance * returned;
        });
}

/// Whether wi lies where the light is not resolved in float (a corner seen
/// at a grazing angle), yet the sampler is right there: the samples of
/// inputs approaching `input` from inside converge to wi, the nearest one's
/// returned L equals `returned`, and further out the returned L agrees with
/// the light's own L (float_probe.h, excused_in_the_limit).
bool agrees_in_the_limit(const LightCase& light, const WarpInput& input, const WarpOutput& wi, float returned) {
    const std::vector<WarpInput> ladder = inward_ladder(input, InputKind::Uniform2D);
    std::vector<LightRecord> rec(ladder.size());
    light.sample_light(ladder, rec);
    std::vector<WarpOutput> xs(ladder.size());
    for (std::size_t k = 0; k < rec.size(); ++k) xs[k] = rec[k].wi;
    std::vector<double> L(ladder.size());
    light.radiance(xs, L);
    const auto agree = [](double a, double b) { return std::abs(a - b) <= kRelativeTolerance * std::max(a, b); };
    if (!rec.front().sampled() || !agree(returned, rec.front().L)) return false;
    std::vector<unsigned char> passes(rec.size());
    for (std::size_t k = 0; k < rec.size(); ++k) passes[k] = rec[k].sampled() && L[k] > 0.0 && agree(rec[k].L, L[k]);
    for (const LightRecord& r : rec)
        if (!r.sampled()) return false;  // a declined step is no sample to converge
    return excused_in_the_limit(light.domain(), wi, xs, passes);
}

/// Whether L(ref, wi) > 0 jumps (kJumpTolerance) within kProbeUlps spacings
/// of each of the samples `which` along a coordinate (axis_probes): wi lies
/// that close to the silhouette or a border, where rounding can carry a
/// sample across. One evaluation of L for all.
std::vector<unsigned char> near_silhouette(const LightCase& light, std::span<const LightRecord> rec,
                                           std::span<const double> L, std::span<const std::size_t> which) {
    return holds_at_a_probe(
        which, [&](std::size_t i) { return axis_probes(light.domain(), rec[i].wi); },
        [&](std::span<const WarpOutput> points) { return radiance_at(light, points); },
        [&](std::size_t i, const std::vector<double>& values, std::size_t j) {
            return std::abs(values[j] - L[i]) > kJumpTolerance * L[i];
        });
}

/// The relative difference of a returned L and the light's own (0 within FLT_MIN).
double relative_l(float returned, double L) {
    const double diff = std::abs(static_cast<double>(returned) - L);
    return diff <= FLT_MIN ? 0.0 : diff / std::max(std::abs(static_cast<double>(returned)), L);
}

RadianceStats compute(const LightCase& light, const CheckContext& ctx) {
    const std::size_t stride = edge_band_stride(ctx.options().samples);
    auto parts = map_input_chunks<RadianceStats>(ctx, InputKind::Uniform2D, ctx.options().samples, true,
                                                 [&](std::size_t chunk, std::span<const WarpInput> inputs) {
        std::vector<LightRecord> rec(inputs.size());
        light.sample_light(inputs, rec);
        std::vector<WarpOutput> wi(inputs.size());
        for (std::size_t i = 0; i < inputs.size(); ++i) wi[i] = rec[i].wi;
        std::vector<double> L(inputs.size());
        light.radiance(wi, L);
        RadianceStats s;
        if (chunk > 0) s.random_count = inputs.size();
        // The samples probed for a silhouette nearby and the mismatches tried
        // at their float neighbours, each set probed in one batch.
        std::vector<std::size_t> banded, mismatched;
        for (std::size_t i = 0; i < inputs.size(); ++i) {
            const LightRecord& r = rec[i];
            if (!r.sampled() || !std::isfinite(r.L) || !(r.L >= 0.0f) || !std::isfinite(L[i])) continue;
            if (chunk > 0 && i % stride == 0 && L[i] > 0.0) banded.push_back(i);
            if (!(r.L == 0.0f && L[i] == 0.0) && !(relative_l(r.L, L[i]) <= kRelativeTolerance)) mismatched.push_back(i);
        }
        const std::vector<unsigned char> near = near_silhouette(light, rec, L, banded);
        const std::vector<unsigned char> agrees = agree_nearby(light, rec, mismatched);
        std::size_t b = 0, m = 0;
        for (std::size_t i = 0; i < inputs.size(); ++i) {
            const uint64_t index = chunk * kInputChunkSize + i;
            const LightRecord& r = rec[i];
            ++s.count;
            if (!r.sampled()) {
                ++s.no_sample;
                s.no_sample_random += chunk > 0 ? 1 : 0;
                continue;
            }
            const Example e{inputs[i], r, L[i]};
            if (!std::isfinite(r.L) || !(r.L >= 0.0f) || !std::isfinite(L[i])) {
                s.invalid.add(index, e);
                continue;
            }
            if (b < banded.size() && banded[b] == i) s.band.add(near[b++] != 0);
            if (light.behind_surface(r.wi)) ++s.behind_surface;
            if (r.L == 0.0f && L[i] == 0.0) {
                ++s.dark;
                continue;
            }
            const double rel = relative_l(r.L, L[i]);
            if (rel <= kRelativeTolerance) continue;
            const bool nearby = m < mismatched.size() && mismatched[m] == i && agrees[m++] != 0;
            const bool limit = chunk == 0 && !nearby && agrees_in_the_limit(light, inputs[i], r.wi, r.L);
            if (nearby || limit) {
                if (chunk == 0) ++s.excused_edges;
                else s.excused_random.add(index, e);
                s.below_resolution += limit ? 1 : 0;
            } else if (L[i] == 0.0) {
                s.misses.add(index, e);
            } else {
                s.max_relative = max_nan_wins(s.max_relative, rel);
                s.mismatches.add(index, e);
            }
        }
        return s;
    });
    return merge_in_order(parts);
}

std::string describe(const Example& e) {
    return fmt::format("u ({:.9g}, {:.9g}) -> wi {}, pdf {:.6g}, returned L {:.9g}, L(ref, wi) {:.9g}",
                       e.input.u[0], e.input.u[1], format_output(e.record.wi, 3), e.record.pdf, e.record.L,
                       e.reference);
}

void judge(CheckResult& r, const RadianceStats& s) {
    const uint64_t sampled = s.count - s.no_sample;
    const uint64_t bound = rounded_across_edge_bound(s.random_count - s.no_sample_random, s.band);
    std::vector<std::string> notes;
    if (s.behind_surface > 0)
        notes.push_back(fmt::format("{} samples lie behind the reference surface", s.behind_surface));
    if (s.dark > 0) notes.push_back(fmt::format("{} samples carry no light (L = 0 on both sides)", s.dark));
    if (s.no_sample > 0) notes.push_back(fmt::format("{} inputs gave no sample (pdf 0)", s.no_sample));
    if (s.excused_edges + s.excused_random.count > 0)
        notes.push_back(fmt::format("{} samples ({} of them edge inputs) find their L only at a float neighbour of "
                                    "wi: rounded across the silhouette (at most {} random ones allowed)",
                                    s.excused_edges + s.excused_random.count, s.excused_edges, bound));
    r.summary = fmt::format("max rel. diff {:.3g}{}", s.max_relative,
                            s.behind_surface > 0 ? fmt::format(", {} behind the surface", s.behind_surface) : "");
    std::vector<std::string> failures;
    if (s.invalid.count > 0)
        failures.push_back(fmt::format("{} samples return a non-finite or negative L, or L(ref, wi) is not finite "
                                       "(first: {})", s.invalid.count, describe(*s.invalid.first)));
    if (s.misses.count > 0)
        failures.push_back(fmt::format("{} samples point where the light's own intersection finds no light, "
                                       "and no float neighbour does (first: {})", s.misses.count,
                                       describe(*s.misses.first)));
    if (s.mismatches.count > 0)
        failures.push_back(fmt::format("{} samples return an L that differs from L(ref, wi) by more than {:.3g} "
                                       "relative (first: {})", s.mismatches.count, kRelativeTolerance,
                                       describe(*s.mismatches.first)));
    if (s.excused_random.count > bound)
        failures.push_back(fmt::format("{} random samples find their L only a float step from wi, more than the {} "
                                       "float rounding puts across a silhouette (first: {})", s.excused_random.count,
                                       bound, describe(*s.excused_random.first)));
    if (failures.empty()) {
        r.verdict = Verdict::Pass;
        r.message = join_reasons(notes);
        return;
    }
    r.verdict = Verdict::Fail;
    r.summary = fmt::format("{} of {} samples wrong", s.invalid.count + s.misses.count + s.mismatches.count, sampled);
    r.message = join_reasons(failures);
    if (!notes.empty()) r.message += "; " + join_reasons(notes);
}

class LightRadianceCheck final : public Check {
public:
    std::string name() const override { return "light_radiance"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"invalid", "samples with a non-finite or negative L, or L(ref, wi) not finite", FigureRule::Zero},
                            {"misses", "samples where the light's own intersection finds no light", FigureRule::Zero},
                            {"mismatches", "samples whose L differs from L(ref, wi) beyond the tolerance", FigureRule::Zero},
                            {"agree_at_neighbour_random", "random samples that agree only at a float neighbour",
                             FigureRule::AtMost, "agree_at_neighbour_bound"},
                            {"agree_at_neighbour_edge_inputs", "edge inputs that agree only at a float neighbour",
                             FigureRule::Counted},
                            {"behind_surface", "samples behind the reference surface", FigureRule::Counted},
                            {"no_sample", "inputs the light declined", FigureRule::Counted}}};
    }
    CheckLegend legend() const override {
        return {name(), "Every sample's L against the light's own L(ref, wi) (finite, > 0, equal within float "
                "rounding): a sampled direction that misses the light fails; misses at the silhouette within a float "
                "step are excused, counted and bounded; samples behind the reference surface or without light are "
                "counted, not failed.",
                ""};
    }
    std::string description() const override {
        return "light: every sample's L equals the light's own L(ref, wi) > 0 (misses named; samples behind the "
               "surface counted)";
    }
    Applicability applicability(const WarpCase& warp) const override {
        return Applicability::when(as_light(warp) != nullptr);
    }
    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const RadianceStats s = compute(*as_light(warp), ctx);
        if (s.count > 0 && s.no_sample == s.count) return nothing_sampled(s.count);
        CheckResult r;
        r.samples = s.count;
        r.figures = {{"samples", static_cast<double>(s.count)},
                     {"no_sample", static_cast<double>(s.no_sample)},
                     {"invalid", static_cast<double>(s.invalid.count)},
                     {"misses", static_cast<double>(s.misses.count)},
                     {"mismatches", static_cast<double>(s.mismatches.count)},
                     {"agree_at_neighbour_edge_inputs", static_cast<double>(s.excused_edges)},
                     {"agree_at_neighbour_random", static_cast<double>(s.excused_random.count)},
                     {"agree_at_neighbour_bound", static_cast<double>(rounded_across_edge_bound(s.random_count - s.no_sample_random, s.band))},
                     {"edge_band_probed", static_cast<double>(s.band.probed)},
                     {"edge_band_near", static_cast<double>(s.band.near)},
                     {"agree_below_resolution", static_cast<double>(s.below_resolution)},
                     {"behind_surface", static_cast<double>(s.behind_surface)},
                     {"dark_samples", static_cast<double>(s.dark)},
                     {"max_relative_difference", s.max_relative},
                     {"tolerance", kRelativeTolerance}};
        judge(r, s);
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_light_radiance_check() { return std::make_unique<LightRadianceCheck>(); }

}  // namespace warpcheck::light
