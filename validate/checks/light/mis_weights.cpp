// "mis_weights": at every direction a strategy of an MIS case samples, the
// weights every strategy would give it sum to 1. Strategy t's weight at wi is
// the heuristic of its own pdf (the density its sample returns, its case's
// pdf()) beside the other strategies' pdfs as the MIS sum evaluates them
// (MisPdfs): where the sum evaluates a strategy with another function (an
// area-measure pdf, a light's pdf without its selection probability), the
// weights of a direction sum to more or less than 1 and the estimator counts
// its light more or less than once. A case whose MIS sum uses the cases' own
// pdfs has weights that sum to 1 by construction: n/a, with that reason.
//
// Deterministic: each strategy samples the run's inputs (edge inputs
// included) and every direction is judged. A direction whose weights sum to
// 1 only at a float neighbour lies on a silhouette that the two pdfs find a
// float step apart; random ones are counted against the bound of the other
// checks (float_probe.h), at the share of random directions measured within
// kProbeUlps float steps of a jump of any strategy's pdf (EdgeBand): a light
// a thousandth of a radian across has a hundred times the fixed rate there.
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
// A named namespace around the file's own names: the unity build compiles
// this file with the other light checks, whose anonymous namespaces hold
// names of their own (Example, compute, Estimates, integrate).
namespace mis_weights_check {
namespace {

/// How far the weights may sum from 1: each MIS pdf may differ from its
/// strategy's own pdf by kReturnedValueTolerance (two float paths to one
/// density), which moves a weight by at most beta / 4 of that relative
/// difference (the heuristic's logarithmic slope, beta w (1 - w)); K such
/// strategies, with a factor 2 for the second order and the sum's rounding.
double tolerance(const MisCase& mis) {
    const double beta = mis.heuristic() == MisHeuristic::Power ? 2.0 : 1.0;
    return static_cast<double>(mis.strategy_count()) * beta * 0.5 * kReturnedValueTolerance;
}

struct Example {
    std::size_t strategy = 0;
    WarpOutput wi{};
    double sum = 0.0;
    std::vector<double> own, mis;
};

struct WeightStats {
    uint64_t count = 0, random_count = 0, no_sample = 0, no_sample_random = 0, unweighted = 0, excused_edges = 0;
    Tally<Example> wrong, excused_random;
    double max_excess = 0.0;
    EdgeBand band;  ///< random directions probed for a jump of a pdf nearby

    void merge(const WeightStats& o) {
        count += o.count;
        random_count += o.random_count;
        no_sample += o.no_sample;
        no_sample_random += o.no_sample_random;
        band.merge(o.band);
        unweighted += o.unweighted;
        excused_edges += o.excused_edges;
        wrong.merge(o.wrong);
        excused_random.merge(o.excused_random);
        max_excess = max_nan_wins(max_excess, o.max_excess);
    }
};

/// Every strategy's own and MIS pdf at each of wi.
struct Pdfs {
    std::vector<std::vector<double>> own, mis;
};

Pdfs evaluate(const MisCase& mis, std::span<const WarpOutput> wi) {
    Pdfs p;
    for (std::size_t t = 0; t < mis.strategy_count(); ++t) {
        p.own.emplace_back(wi.size());
        p.mis.emplace_back(wi.size());
        mis.strategy_pdf(t, wi, p.own.back());
        mis.mis_pdf(t, wi, p.mis.back());
    }
    return p;
}

/// The sum of the weights at direction i, NaN where a pdf is not finite; 0
/// where no strategy's own pdf is positive (no strategy samples there).
double weight_sum(const MisCase& mis, const Pdfs& p, std::size_t i) {
    const std::size_t k = mis.strategy_count();
    std::vector<double> others(k - 1);
    double sum = 0.0;
    for (std::size_t t = 0; t < k; ++t) {
        const double own = p.own[t][i];
        if (!std::isfinite(own) || !std::isfinite(p.mis[t][i])) return std::nan("");
        if (!(own > 0.0)) continue;
        for (std::size_t j = 0, m = 0; j < k; ++j)
            if (j != t) others[m++] = p.mis[j][i];
        sum += mis.weight(own, others);
    }
    return sum;
}

/// Whether the weights sum to 1 at a float neighbour of each of the
/// directions `which`: wi was rounded across a silhouette that the two pdfs
/// find a float step apart. One evaluation of the pdfs for all (ProbeBatch).
std::vector<unsigned char> sum_to_one_nearby(const MisCase& mis, std::span<const WarpOutput> wi,
                                             std::span<const std::size_t> which, double tol) {
    return holds_at_a_probe(
        which, [&](std::size_t i) { return float_neighbours(wi[i]); },
        [&](std::span<const WarpOutput> points) { return evaluate(mis, points); },
        [&](std::size_t, const Pdfs& p, std::size_t j) { return std::abs(weight_sum(mis, p, j) - 1.0) <= tol; });
}

/// Whether a strategy's own or MIS pdf jumps (kJumpTolerance of the larger
/// value) within kProbeUlps spacings of each of the directions `which` along
/// a coordinate (axis_probes): wi lies that close to a silhouette, where
/// rounding can carry it across. One evaluation of the pdfs for all.
std::vector<unsigned char> near_jump(const MisCase& mis, const Pdfs& at, std::span<const WarpOutput> wi,
                                     std::span<const std::size_t> which) {
    const auto jumps = [](double a, double b) {
        return !(std::abs(a - b) <= kJumpTolerance * std::max(std::abs(a), std::abs(b)));
    };
    return holds_at_a_probe(
        which, [&](std::size_t i) { return axis_probes(mis.domain(), wi[i]); },
        [&](std::span<const WarpOutput> points) { return evaluate(mis, points); },
        [&](std::size_t i, const Pdfs& p, std::size_t j) {
            for (std::size_t t = 0; t < mis.strategy_count(); ++t)
                if (jumps(p.own[t][j], at.own[t][i]) || jumps(p.mis[t][j], at.mis[t][i])) return true;
            return false;
        });
}

WeightStats compute(const MisCase& mis, const CheckContext& ctx) {
    const double tol = tolerance(mis);
    const std::size_t stride = edge_band_stride(ctx.options().samples);
    auto parts = map_input_chunks<WeightStats>(ctx, InputKind::Uniform3D, ctx.options().samples, true,
                                               [&](std::size_t chunk, std::span<const WarpInput> inputs) {
        WeightStats s;
        std::vector<MisRecord> rec(inputs.size());
        std::vector<WarpOutput> wi(inputs.size());
        for (std::size_t t = 0; t < mis.strategy_count(); ++t) {
            mis.sample_strategy(t, inputs, rec);
            for (std::size_t i = 0; i < inputs.size(); ++i) wi[i] = rec[i].wi;
            const Pdfs p = evaluate(mis, wi);
            if (chunk > 0) s.random_count += inputs.size();
            // The directions probed for a jump nearby and the wrong sums tried
            // at their float neighbours, each set probed in one batch.
            std::vector<double> sums(inputs.size(), 0.0);
            std::vector<std::size_t> banded, wrong;
            for (std::size_t i = 0; i < inputs.size(); ++i) {
                if (!rec[i].sampled() || !std::isfinite(wi[i][0] + wi[i][1] + wi[i][2])) continue;
                sums[i] = weight_sum(mis, p, i);
                if (chunk > 0 && i % stride == 0 && std::isfinite(sums[i])) banded.push_back(i);
                if (sums[i] != 0.0 && !(std::abs(sums[i] - 1.0) <= tol) && std::isfinite(sums[i])) wrong.push_back(i);
            }
            const std::vector<unsigned char> near = near_jump(mis, p, wi, banded);
            const std::vector<unsigned char> nearby = sum_to_one_nearby(mis, wi, wrong, tol);
            for (std::size_t i = 0, b = 0, w = 0; i < inputs.size(); ++i) {
                ++s.count;
                if (!rec[i].sampled() || !std::isfinite(wi[i][0] + wi[i][1] + wi[i][2])) {
                    ++s.no_sample;
                    s.no_sample_random += chunk > 0 ? 1 : 0;
                    continue;
                }
                const double sum = sums[i];
                if (b < banded.size() && banded[b] == i) s.band.add(near[b++] != 0);
                if (sum == 0.0) {
                    ++s.unweighted;  // no own pdf is positive here: sample_pdf's finding, not a weight's
                    continue;
                }
                const double excess = std::abs(sum - 1.0);
                if (excess <= tol) continue;
                Example e{t, wi[i], sum, {}, {}};
                for (std::size_t j = 0; j < mis.strategy_count(); ++j)
                    e.own.push_back(p.own[j][i]), e.mis.push_back(p.mis[j][i]);
                const uint64_t index = (uint64_t{t} << 48) + chunk * kInputChunkSize + i;
                if (w < wrong.size() && wrong[w] == i && nearby[w++] != 0) {
                    if (chunk == 0) ++s.excused_edges;
                    else s.excused_random.add(index, e);
                    continue;
                }
                s.max_excess = max_nan_wins(s.max_excess, excess);
                s.wrong.add(index, e);
            }
        }
        return s;
    });
    return merge_in_order(parts);
}

std::string describe(const MisCase& mis, const Example& e) {
    std::string pdfs;
    for (std::size_t t = 0; t < e.own.size(); ++t)
        pdfs += fmt::format("{}{}: pdf {:.6g}, in the MIS sum {:.6g}", t == 0 ? "" : "; ", mis.strategy_name(t),
                            e.own[t], e.mis[t]);
    return fmt::format("wi {} sampled by {}: weights sum to {:.9g} ({})", format_output(e.wi, 3),
                       mis.strategy_name(e.strategy), e.sum, pdfs);
}

class MisWeightsCheck final : public Check {
public:
    std::string name() const override { return "mis_weights"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"wrong_sums", "sampled directions whose weights do not sum to 1, nor at a float neighbour",
                             FigureRule::Zero},
                            {"agree_at_neighbour_random", "random directions that sum to 1 only at a float neighbour",
                             FigureRule::AtMost, "agree_at_neighbour_bound"},
                            {"agree_at_neighbour_edge_inputs", "edge inputs that sum to 1 only at a float neighbour",
                             FigureRule::Counted},
                            {"max_excess", "largest |sum of weights \u2212 1|", FigureRule::Counted},
                            {"no_sample", "inputs a strategy declined", FigureRule::Counted}}};
    }
    CheckLegend legend() const override {
        return {name(), "At every direction a strategy samples, the weights of all strategies (each one's own pdf "
                "beside the others' pdfs as the MIS sum evaluates them) sum to 1; sums that reach 1 only at a float "
                "neighbour are counted and bounded; a case whose sum uses the cases' own pdfs is n/a.",
                ""};
    }
    std::string description() const override {
        return "MIS: at every sampled direction the strategies' weights (each one's own pdf beside the others' "
               "pdfs as the MIS sum evaluates them) sum to 1";
    }
    Applicability applicability(const WarpCase& warp) const override {
        const MisCase* mis = as_mis(warp);
        if (mis == nullptr) return Applicability::when(false);
        for (std::size_t s = 0; s < mis->strategy_count(); ++s)
            if (mis->has_mis_pdf(s)) return Applicability::when(true);
        return Applicability::lacks("the MIS sum uses each case's own pdf(): the weights sum to 1 by construction");
    }
    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const MisCase& mis = *as_mis(warp);
        const WeightStats s = compute(mis, ctx);
        const uint64_t bound = rounded_across_edge_bound(s.random_count - s.no_sample_random, s.band);
        const double tol = tolerance(mis);
        CheckResult r;
        r.samples = s.count;
        r.figures = {{"directions", static_cast<double>(s.count)},
                     {"no_sample", static_cast<double>(s.no_sample)},
                     {"unweighted", static_cast<double>(s.unweighted)},
                     {"wrong_sums", static_cast<double>(s.wrong.count)},
                     {"max_excess", s.max_excess},
                     {"agree_at_neighbour_edge_inputs", static_cast<double>(s.excused_edges)},
                     {"agree_at_neighbour_random", static_cast<double>(s.excused_random.count)},
                     {"agree_at_neighbour_bound", static_cast<double>(bound)},
                     {"edge_band_probed", static_cast<double>(s.band.probed)},
                     {"edge_band_near", static_cast<double>(s.band.near)},
                     {"tolerance", tol}};
        std::vector<std::string> notes;
        if (s.unweighted > 0)
            notes.push_back(fmt::format("{} sampled directions have no positive own pdf (sample_pdf judges them)",
                                        s.unweighted));
        if (s.excused_edges + s.excused_random.count > 0)
            notes.push_back(fmt::format("{} directions ({} of them from edge inputs) sum to 1 only at a float "
                                        "neighbour: a silhouette the two pdfs find a float step apart (at most {} "
                                        "random ones allowed)", s.excused_edges + s.excused_random.count,
                                        s.excused_edges, bound));
        std::vector<std::string> failures;
        if (s.wrong.count > 0)
            failures.push_back(fmt::format("{} sampled directions have weights that do not sum to 1 within {:.3g}, "
                                           "nor at a float neighbour: the MIS sum evaluates a strategy with another "
                                           "pdf than the density its sampler draws from (first: {})",
                                           s.wrong.count, tol, describe(mis, *s.wrong.first)));
        if (s.excused_random.count > bound)
            failures.push_back(fmt::format("{} random directions sum to 1 only a float step away, more than the {} "
                                           "float rounding puts across a silhouette (first: {})",
                                           s.excused_random.count, bound, describe(mis, *s.excused_random.first)));
        r.summary = fmt::format("max |sum - 1| {:.3g} over {} directions", s.max_excess, s.count - s.no_sample);
        if (failures.empty()) {
            r.verdict = Verdict::Pass;
            r.message = join_reasons(notes);
            return r;
        }
        r.verdict = Verdict::Fail;
        r.summary = fmt::format("{} of {} weight sums wrong", s.wrong.count, s.count - s.no_sample);
        r.message = join_reasons(failures);
        if (!notes.empty()) r.message += "; " + join_reasons(notes);
        return r;
    }
};

}  // namespace
}  // namespace mis_weights_check

std::unique_ptr<Check> make_mis_weights_check() { return std::make_unique<mis_weights_check::MisWeightsCheck>(); }

}  // namespace warpcheck::light
