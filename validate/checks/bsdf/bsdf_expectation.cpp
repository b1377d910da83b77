// "bsdf_expectation": a stochastic BSDF (BsdfClaims::stochastic: a layered
// BSDF whose f is a random-walk estimate and whose sampler returns a
// throughput with a pdf that is only proportional) tested in expectation,
// where every pointwise comparison would fail by design.
//
// What holds in expectation: for every region C of the sphere, the sampled
// weights that land in C average to the integral of f |cos theta_i| over C,
//     E[w 1(wi in C)] = integral over C of E[f(wo, wi)] |cos theta_i| dwi,
// w = f |cos theta_i| / pdf of the sample's own return (0 without a sample),
// since both sides are unbiased whatever the estimators' variance. The check
// estimates each side independently per cell of a sphere chart (16 azimuths
// by 16 heights of cos theta on each side its lobes claim, cells of equal
// solid angle): the left from the draws, the right from f() at directions
// uniform in the cell (an independent stream; evaluations allotted half by
// the cells' share of a pilot's weight, half evenly), and compares them by a
// z-test with both measured variances. Rules:
//  - a cell is judged on its own when each side is expected to have at least
//    50 effective terms ((sum x)^2 / sum x^2), as projected from pilots (an
//    eighth of the draws from the pilot streams, an eighth of the reference
//    from streams of its own): with fewer, a mean of skewed terms and its
//    variance estimate move together, and its z strays beyond the normal
//    tails the run's level reads. The decision looks at no tested number, so
//    it selects no cell by its noise. The other cells with mass are pooled
//    into one remainder, judged the same way where its pilots promise 50
//    terms, else excused, with their count and their share of the weight and
//    of the integral reported (the total below still holds them);
//  - a comparison whose p falls below 0.01 over the cells is made again
//    against a fresh reference 16 times larger (kRetestFactor says why), and
//    its p is the larger of the two; the fresh reference serves that
//    comparison alone (retest() says why), and the evaluations of every
//    reference made count in the exact rule below;
//  - the total: the mean continuous weight against the integral over the
//    whole sphere (the albedo of the continuous lobes), the same z-test;
//  - energy: the mean energy weight of all draws, delta lobes included, at
//    most 1 (one-sided t-test, 2^-20 for the bound's rounding, as bsdf_energy);
//    the p-values of all these tests combine by Sidak's min-p (at these
//    levels within a hair of Bonferroni's, which holds whatever the tests'
//    correlation), judged by the runner at the run's level;
//  - exact rules (a count, no tolerance): every draw's weight finite and not
//    negative, its wi a finite unit vector (within 2^-10, a renderer's float
//    normalisation) on a side the lobes claim; pdf(wo, wi) finite and positive
//    at every continuous sample's wi: a direction the sampler draws where the
//    MIS pdf is 0 gives its light-sampling strategy the MIS weight 1 there,
//    and the weights no longer sum to 1.
//  - reciprocity in expectation, where the case claims it: at the reference's
//    directions wi, f(wi, wo) is evaluated too, and the paired differences
//    f(wo, wi) s - f(wi, wo) (s the claimed rule's scale, bsdf_common.h) must
//    average to 0 per cell: the estimates' expectations obey the rule that
//    bsdf_reciprocity holds a deterministic f to pointwise. Pairing cancels
//    f's smooth change across a cell, so the test sees the estimates' noise
//    only. Cells are judged alone, pooled, retested and excused as the
//    weights' are, by the effective count of the differences' magnitudes
//    (their mean is 0 under the claim), and a cell whose differences are all
//    exactly 0 is counted exact, with no test; the total over the sphere is
//    judged too. The z-test allows a mean asymmetry of kReciprocityTolerance of the
//    cell's integral of f(wi, wo): the pointwise check's allowance for f's
//    float rounding, a bias that no count of evaluations averages away. Every
//    reference evaluation of f, in either order, must be finite and not
//    negative (a count);
// The integral of pdf(wo, .) over the sphere (by the same evaluations) is
// stated, not judged: an MIS pdf need not be normalised.
// Power: the relative shift of the total, and of the heaviest cell, that the
// row detects with probability 0.9 at the level of a typical run; for
// reciprocity, the relative asymmetry of the heaviest cell (by f(wi, wo)).
// A cell's edges are compared in double with the float directions of the
// samples: a sample within float rounding of an edge may change cells, a bias
// of about 2^-24 of a cell's mass, far below the noise of 10^6 draws.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "chi2/mean_test.h"
#include "chi2/min_p.h"
#include "validate/checks/bsdf/bsdf_checks.h"
#include "validate/checks/bsdf/bsdf_common.h"
#include "validate/checks/bsdf/bsdf_statistics.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/power_level.h"

namespace warpcheck::bsdf {
namespace expectation_detail {

constexpr int kAzimuths = 16, kHeights = 16, kCellsPerSide = kAzimuths * kHeights;
/// Effective terms a side needs for its z-test (the rules above say why 50:
/// at 50 equal terms a sum's skewness is 1/7 of one term's).
constexpr double kMinEffectiveTerms = 50.0;
/// The reference's streams start here, beyond any chunk of draws.
constexpr uint64_t kReferenceChunks = uint64_t{1} << 40;
/// The pilot reference's share of the reference's evaluations, and its streams.
constexpr double kPilotShare = 0.125;
constexpr uint64_t kPilotReferenceChunks = kReferenceChunks + (uint64_t{1} << 21);
/// The retest of a cell whose z-test flags it (p below kScreenAlpha over the
/// cells): a fresh reference kRetestFactor times larger, from streams beyond
/// the first reference's, and the cell's p the larger of the two. A reference
/// f that is an estimate with a heavy tail (a walk's next-event term on a sharp
/// base: rare large values) is a mean whose variance estimate falls with it, so
/// its z-test fails correct cells more often than its level says; 16 times the
/// evaluations see the tail 16 times as often, and an error in the sampler or
/// in f fails both tests alike.
constexpr double kScreenAlpha = 0.01;
constexpr uint64_t kRetestFactor = 16;
constexpr uint64_t kRetestChunks = kReferenceChunks + (uint64_t{1} << 20);
/// A unit vector's length, within a renderer's float normalisation.
constexpr double kUnitTolerance = 0x1p-10;
/// The energy bound's rounding (bsdf_albedo's kRoundingAllowance).
constexpr double kEnergyRounding = 0x1p-20;

/// The sides of the sphere the case's cells cover: +1 (z > 0), -1, or both.
std::vector<int> sides_of(const BsdfCase& bsdf) {
    if (bsdf.phase_function()) return {1, -1};
    const int own = bsdf.wo().z > 0.0f ? 1 : -1;
    std::vector<int> sides;
    if (has(bsdf.claims().lobes, BsdfFlags::Reflection)) sides.push_back(own);
    if (has(bsdf.claims().lobes, BsdfFlags::Transmission)) sides.push_back(-own);
    return sides;
}

/// The cell of a direction among the sides' cells, or -1 off every side. A
/// wi on the horizon (z = 0, weight 0 for a BSDF) goes to the first side.
int cell_of(const std::vector<int>& sides, const WarpOutput& wi) {
    const double z = wi[2];
    for (std::size_t s = 0; s < sides.size(); ++s) {
        if (!(z * sides[s] > 0.0 || (z == 0.0 && s == 0))) continue;
        const double phi = std::atan2(static_cast<double>(wi[1]), static_cast<double>(wi[0]));
        const double turn = (phi < 0.0 ? phi + 2.0 * std::numbers::pi : phi) / (2.0 * std::numbers::pi);
        const int a = std::min(kAzimuths - 1, static_cast<int>(turn * kAzimuths));
        const int h = std::min(kHeights - 1, static_cast<int>(std::abs(z) * kHeights));
        return static_cast<int>(s) * kCellsPerSide + h * kAzimuths + a;
    }
    return -1;
}

/// Sums of a side's terms over a cell (or a pool of cells): the estimate is
/// `sum`, its variance `variance`, and `squares` the sum of the terms'
/// squares (for the effective count). A sampled side also keeps the raw sums
/// of its weights and their squares (the tested draws' and the pilot's) and
/// the number of tested draws, for its variance under the null hypothesis.
struct Side {
    double sum = 0.0, variance = 0.0, squares = 0.0;
    double raw = 0.0, raw_squares = 0.0, draws = 0.0;
    void add(const Side& o) {
        sum += o.sum;
        variance += o.variance;
        squares += o.squares;
        raw += o.raw;
        raw_squares += o.raw_squares;
        draws = std::max(draws, o.draws);
    }
    /// (sum x)^2 / sum x^2; 0 for a side that saw nothing (no draw landed, or
    /// f was 0 at every direction tried): that is no evidence of a zero.
    double effective_terms() const { return squares > 0.0 ? sum * sum / squares : 0.0; }
};

struct DrawTally {
    std::vector<double> weight, square;  ///< per cell: sum of w, of w^2
    chi2::Moments continuous, energy;
    uint64_t draws = 0, bad_weight = 0, bad_direction = 0, off_side = 0, pdf_zero = 0;
    std::string first_problem;
    void merge(const DrawTally& o) {
        if (weight.empty()) weight.assign(o.weight.size(), 0.0), square.assign(o.square.size(), 0.0);
        for (std::size_t c = 0; c < o.weight.size(); ++c) weight[c] += o.weight[c], square[c] += o.square[c];
        continuous.merge(o.continuous);
        energy.merge(o.energy);
        draws += o.draws, bad_weight += o.bad_weight, bad_direction += o.bad_direction;
        off_side += o.off_side, pdf_zero += o.pdf_zero;
        if (first_problem.empty()) first_problem = o.first_problem;
    }
};

void note_problem(DrawTally& t, uint64_t& count, const WarpInput& in, const BsdfRecord& r, const char* what) {
    ++count;
    if (t.first_problem.empty())
        t.first_problem = fmt::format("{} at u = ({:.9g}, {:.9g}, {:.9g}): wi ({:.9g}, {:.9g}, {:.9g}), f {:.9g}, pdf "
                                      "{:.9g}",
                                      what, in.u[0], in.u[1], in.u[2], r.wi[0], r.wi[1], r.wi[2], r.f, r.pdf);
}

/// One draw into the tally (`random`: it enters the means; edge inputs only
/// face the exact rules).
void tally_draw(const BsdfCase& bsdf, const std::vector<int>& sides, const WarpInput& in, const BsdfRecord& r,
                bool random, DrawTally& t) {
    double w = 0.0;
    if (r.sampled()) {
        w = static_cast<double>(r.f) * bsdf.cosine(r.wi) / r.pdf;
        const double len = std::hypot(static_cast<double>(r.wi[0]), static_cast<double>(r.wi[1]),
                                      static_cast<double>(r.wi[2]));
        if (!(w >= 0.0 && std::isfinite(w))) note_problem(t, t.bad_weight, in, r, "a weight not finite or negative");
        if (!(std::abs(len - 1.0) <= kUnitTolerance)) note_problem(t, t.bad_direction, in, r, "wi not a unit vector");
        if (!r.delta()) {
            const int c = cell_of(sides, r.wi);
            if (c < 0) note_problem(t, t.off_side, in, r, "wi on a side its lobes do not claim");
            std::array<double, 1> pdf{};
            bsdf.pdf(std::span<const WarpOutput>(&r.wi, 1), pdf);
            if (!(pdf[0] > 0.0 && std::isfinite(pdf[0]))) note_problem(t, t.pdf_zero, in, r, "pdf(wo, wi) not positive");
            if (random && c >= 0 && std::isfinite(w)) {
                t.weight[static_cast<std::size_t>(c)] += w;
                t.square[static_cast<std::size_t>(c)] += w * w;
            }
        }
    }
    if (!random) return;
    ++t.draws;
    t.continuous.add(r.sampled() && !r.delta() ? w : 0.0);
    t.energy.add(r.sampled() ? w * bsdf.energy_factor(r.wi) : 0.0);
}

DrawTally draw(const BsdfCase& bsdf, const CheckContext& ctx, const std::vector<int>& sides) {
    const std::size_t cells = sides.size() * kCellsPerSide;
    const auto parts = map_bsdf_chunks<DrawTally>(
        ctx, bsdf, ctx.options().samples, true,
        [&](std::size_t chunk, std::span<const WarpInput> in, std::span<const BsdfRecord> rec) {
            DrawTally t;
            t.weight.assign(cells, 0.0);
            t.square.assign(cells, 0.0);
            for (std::size_t k = 0; k < rec.size(); ++k) tally_draw(bsdf, sides, in[k], rec[k], chunk != 0, t);
            return t;
        });
    return merge_in_order(parts);
}

/// The sampled side of each cell: the mean of w 1(wi in cell) over the draws,
/// with the raw sums of `t` and of `pilot` (when given) for null_variance.
std::vector<Side> sampled_sides(const DrawTally& t, const DrawTally* pilot = nullptr) {
    const double n = static_cast<double>(t.draws);
    std::vector<Side> out(t.weight.size());
    for (std::size_t c = 0; c < out.size(); ++c) {
        const double mean = t.weight[c] / n;
        out[c] = {mean, std::max(0.0, t.square[c] / n - mean * mean) / (n - 1.0), t.square[c] / (n * n)};
        out[c].raw = t.weight[c] + (pilot ? pilot->weight[c] : 0.0);
        out[c].raw_squares = t.square[c] + (pilot ? pilot->square[c] : 0.0);
        out[c].draws = n;
    }
    return out;
}

struct Reference {
    Side f;            ///< the integral of f |cos| over the cell
    double pdf = 0.0;  ///< the integral of pdf(wo, .) over the cell
    uint64_t evaluations = 0;
    /// Where reciprocity is claimed: the integral over the cell of
    /// f(wo, wi) s - f(wi, wo) (s the claimed rule's scale), both evaluated at
    /// the same directions (paired: f's smooth change across the cell cancels
    /// and only the estimates' noise is left); `asymmetry_size` sums the
    /// differences' magnitudes (its sum) and squares, for the effective count
    /// of a mean that is 0 under the claim; `reverse` the integral of f(wi, wo).
    Side asymmetry, asymmetry_size;
    double reverse = 0.0;
    uint64_t bad_values = 0;  ///< f(wo, wi) or f(wi, wo) not finite or negative
};

/// The integrals over cell c of f |cos| and of pdf, from m directions
/// uniform in the cell (uniform in phi and cos theta is uniform in solid angle).
Reference integrate_cell(const BsdfCase& bsdf, const CheckContext& ctx, const std::vector<int>& sides, std::size_t c,
                         uint64_t m, uint64_t stream) {
    const int side = sides[c / kCellsPerSide];
    const int h = static_cast<int>(c % kCellsPerSide) / kAzimuths, a = static_cast<int>(c % kAzimuths);
    const double area = 2.0 * std::numbers::pi / kAzimuths / kHeights;
    Pcg32 rng = ctx.chunk_rng(stream);
    std::vector<WarpOutput> wi(static_cast<std::size_t>(m));
    for (WarpOutput& w : wi) {
        const double phi = 2.0 * std::numbers::pi * (a + rng.next_double()) / kAzimuths;
        const double z = (h + rng.next_double()) / kHeights, r = std::sqrt(std::max(0.0, 1.0 - z * z));
        w = {static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)), static_cast<float>(side * z)};
    }
    const std::vector<WarpOutput> wo(wi.size(), detail::to_output_of(bsdf.wo()));
    const bool reciprocal = bsdf.claims().reciprocal;
    std::vector<double> fc(wi.size()), pdf(wi.size()), back(reciprocal ? wi.size() : 0);
    bsdf.f(wo, wi, fc);  // f(wo, wi); times |cos| below, as BsdfCase::f_cos does
    if (reciprocal) bsdf.f(wi, wo, back);
    bsdf.pdf(wi, pdf);
    chi2::Moments y, d;
    Reference out;
    for (std::size_t k = 0; k < wi.size(); ++k) {
        const double forward = fc[k];
        fc[k] *= bsdf.cosine(wi[k]);
        y.add(area * fc[k]);
        out.f.squares += area * fc[k] * area * fc[k];
        out.pdf += area * pdf[k];
        out.bad_values += !(forward >= 0.0 && std::isfinite(forward));
        if (!reciprocal) continue;
        out.bad_values += !(back[k] >= 0.0 && std::isfinite(back[k]));
        const double diff = area * (forward * reciprocity_scale(bsdf, wi[k]) - back[k]);
        d.add(diff);
        out.asymmetry_size.sum += std::abs(diff);
        out.asymmetry_size.squares += diff * diff;
        out.reverse += area * back[k];
    }
    const double md = static_cast<double>(m);
    out.f.sum = y.mean;
    out.f.variance = m > 1 ? y.variance() / md : 0.0;
    out.f.squares /= md * md;
    out.pdf /= md;
    out.evaluations = m;
    if (reciprocal) {
        out.asymmetry = {d.mean, m > 1 ? d.variance() / md : 0.0, out.asymmetry_size.squares / (md * md)};
        out.asymmetry_size.sum /= md;
        out.asymmetry_size.squares /= md * md;
        out.reverse /= md;
    }
    return out;
}

/// The tally of `count` draws from the pilot streams.
DrawTally pilot_draws(const BsdfCase& bsdf, const CheckContext& ctx, const std::vector<int>& sides, std::size_t count) {
    const std::vector<WarpInput> in = pilot_inputs(ctx, InputKind::Uniform3D, count);
    std::vector<BsdfRecord> records(in.size());
    bsdf.sample_bsdf(in, records);
    DrawTally t;
    t.weight.assign(sides.size() * kCellsPerSide, 0.0);
    t.square.assign(t.weight.size(), 0.0);
    for (std::size_t k = 0; k < in.size(); ++k) tally_draw(bsdf, sides, in[k], records[k], true, t);
    return t;
}

/// The reference of every cell, evaluations allotted half by the cells' share
/// of sampled weight and half evenly (at least 64 each), samples() in all
/// (by the pilot draws), with `fraction` of them from the streams at `stream`.
std::vector<Reference> reference(const BsdfCase& bsdf, const CheckContext& ctx, const std::vector<int>& sides,
                                 const std::vector<Side>& pilot, double fraction, uint64_t stream) {
    double total = 0.0;
    for (const Side& s : pilot) total += s.sum;
    const double budget = static_cast<double>(ctx.options().samples), cells = static_cast<double>(pilot.size());
    std::vector<Reference> out(pilot.size());
    ctx.parallel_for(out.size(), [&](std::size_t c) {
        ctx.throw_if_cancelled();
        const double share = 0.5 / cells + (total > 0.0 ? 0.5 * pilot[c].sum / total : 0.5 / cells);
        const double m = std::max(64.0, std::floor(budget * share));
        out[c] = integrate_cell(bsdf, ctx, sides, c, static_cast<uint64_t>(std::max(8.0, std::floor(m * fraction))),
                                stream + c);
    });
    return out;
}

/// A side as it would be with `ratio` times its terms: the same estimate,
/// its variance and sum of squared terms divided by the ratio.
Side projected(const Side& s, double ratio) { return {s.sum, s.variance / ratio, s.squares / ratio}; }

bool enough_terms(const Side& sampled, const Side& f) {
    return sampled.effective_terms() >= kMinEffectiveTerms && f.effective_terms() >= kMinEffectiveTerms;
}

/// Which comparisons are made, decided from pilots alone (draws from the
/// pilot streams, kPilotShare of the reference's evaluations from streams of
/// their own), projected to the full counts: a decision that looked at the
/// tested draws or the reference would select cells by their noise (pooling
/// the cells that drew few samples biases the remainder low).
struct Plan {
    std::vector<char> alone;  ///< per cell: judged on its own
    bool remainder = false;   ///< the pool of the other cells with mass is judged
    /// The same for reciprocity in expectation (where claimed): a cell's
    /// paired differences judged alone where the pilot promises 50 effective
    /// terms of their magnitudes, the others pooled.
    std::vector<char> reciprocity_alone;
    bool reciprocity_remainder = false;
};

Plan plan_from_pilots(const std::vector<Side>& pilot_sampled, double draw_ratio, const std::vector<Reference>& pilot_ref,
                      const std::vector<Reference>& ref) {
    Plan plan;
    plan.alone.assign(ref.size(), 0);
    Side rest_s, rest_f;
    for (std::size_t c = 0; c < ref.size(); ++c) {
        const Side s = projected(pilot_sampled[c], draw_ratio);
        const Side f = projected(pilot_ref[c].f, static_cast<double>(ref[c].evaluations) /
                                                     static_cast<double>(pilot_ref[c].evaluations));
        plan.alone[c] = enough_terms(s, f);
        if (!plan.alone[c]) rest_s.add(s), rest_f.add(f);
    }
    plan.remainder = enough_terms(rest_s, rest_f);
    plan.reciprocity_alone.assign(ref.size(), 0);
    Side rest_size;
    for (std::size_t c = 0; c < ref.size(); ++c) {
        const Side size = projected(pilot_ref[c].asymmetry_size, static_cast<double>(ref[c].evaluations) /
                                                                     static_cast<double>(pilot_ref[c].evaluations));
        plan.reciprocity_alone[c] = size.effective_terms() >= kMinEffectiveTerms;
        if (!plan.reciprocity_alone[c]) rest_size.add(size);
    }
    plan.reciprocity_remainder = rest_size.effective_terms() >= kMinEffectiveTerms;
    return plan;
}

struct Comparison {
    double z = 0.0, p = 1.0, sampled = 0.0, integral = 0.0, standard_error = 0.0;
};

/// The sampled side's variance under the null hypothesis that its mean is the
/// reference's m: (rho m - m^2) / (n - 1), rho = E[w^2] / E[w] over the draws
/// that landed (the tested ones and the pilot's). The variance the draws
/// measure falls with their count, so a cell that drew few samples by chance
/// would look surer of its deficit than it is (a Wald test of a count); the
/// score test's variance does not move with it. The measured one where the
/// side has no weights or the reference no mass.
double null_variance(const Side& s, double m) {
    if (!(s.raw > 0.0 && m > 0.0 && s.draws > 1.0)) return s.variance;
    return std::max(0.0, s.raw_squares / s.raw * m - m * m) / (s.draws - 1.0);
}

/// Reciprocity in expectation over a cell (or a pool): the mean paired
/// difference f(wo, wi) s - f(wi, wo) against 0, by a z-test with its measured
/// variance, beyond kReciprocityTolerance of the reverse integral: the
/// pointwise check's allowance for f's float rounding, a bias of the two
/// orders' arithmetic that no count of evaluations averages away.
Comparison compare_reciprocity(const Side& asymmetry, double reverse) {
    Comparison c{0.0, 1.0, asymmetry.sum, reverse, std::sqrt(asymmetry.variance)};
    const double excess = std::abs(asymmetry.sum) - kReciprocityTolerance * std::abs(reverse);
    if (std::isnan(excess) || std::isnan(c.standard_error)) return {NAN, NAN, asymmetry.sum, reverse, NAN};
    if (!(excess > 0.0)) return c;
    c.z = std::copysign(excess, asymmetry.sum) / c.standard_error;  // no variance: infinite, p 0
    c.p = std::erfc(std::abs(c.z) / std::numbers::sqrt2);
    return c;
}

Comparison compare(const Side& s, const Side& f) {
    Comparison c{0.0, 1.0, s.sum, f.sum, std::sqrt(null_variance(s, f.sum) + f.variance)};
    const double d = s.sum - f.sum;
    if (d == 0.0) return c;
    c.z = d / c.standard_error;  // d != 0 with no variance: infinite, p 0; NaN stays NaN
    c.p = std::erfc(std::abs(c.z) / std::numbers::sqrt2);
    return c;
}

struct Outcome {
    std::vector<Comparison> cells;  ///< judged alone
    Comparison remainder, total;
    bool remainder_judged = false;
    int pooled = 0, excused = 0, retested = 0;
    double excused_weight = 0.0, excused_integral = 0.0;  ///< shares of the totals
    chi2::MeanTest energy;
    double pdf_integral = 0.0;
    uint64_t evaluations = 0;
    std::vector<double> p_values;
    int heaviest = -1;  ///< among cells, by sampled weight
    /// Reciprocity in expectation, where the case claims it.
    struct Reciprocity {
        bool tested = false, remainder_judged = false;
        std::vector<Comparison> cells;  ///< judged alone
        Comparison remainder, total;
        int pooled = 0, excused = 0, retested = 0;
        /// Cells where every paired difference is exactly 0 (a deterministic
        /// f that is reciprocal to the bit): the rule holds at each pair, and
        /// no z-test is made; in a pool they would add 0 to its sum and its
        /// variance, and only their integral to its allowance.
        int exact = 0;
        double excused_share = 0.0;  ///< of the reverse integral
        int heaviest = -1;           ///< among cells, by the reverse integral
        int heaviest_cell = -1;      ///< its index in the chart (cell_of)
    } reciprocity;
    uint64_t bad_f_values = 0;  ///< reference evaluations of f (either order) not finite or negative
};

/// The p-values of the first comparisons that were retested (NaN where not):
/// per cell judged alone, and of the remainder, the pool of the others.
struct Screen {
    std::vector<double> cell;
    double remainder = NAN;
    std::vector<double> reciprocity_cell;  ///< the same for reciprocity in expectation
    double reciprocity_remainder = NAN;
    /// Over every reference made (the first and the retests'): evaluations of
    /// f, and those not finite or negative, which fail wherever they were.
    uint64_t evaluations = 0, bad_values = 0;
};

bool has_asymmetry_mass(const Reference& r) { return !(r.reverse == 0.0 && r.asymmetry_size.sum == 0.0); }

/// The reciprocity comparisons' screen, as retest's: flagged cells appended.
void screen_reciprocity(const std::vector<Reference>& ref, const Plan& plan, double threshold, Screen& screen,
                        std::vector<std::size_t>& flagged) {
    screen.reciprocity_cell.assign(ref.size(), NAN);
    std::vector<std::size_t> pool;
    Side rest;
    double rest_reverse = 0.0;
    for (std::size_t c = 0; c < ref.size(); ++c) {
        if (!has_asymmetry_mass(ref[c])) continue;
        if (!plan.reciprocity_alone[c]) {
            rest.add(ref[c].asymmetry), rest_reverse += ref[c].reverse, pool.push_back(c);
            continue;
        }
        const double p = compare_reciprocity(ref[c].asymmetry, ref[c].reverse).p;
        if (!(p >= threshold)) screen.reciprocity_cell[c] = p, flagged.push_back(c);
    }
    const double p_rest = compare_reciprocity(rest, rest_reverse).p;
    if (plan.reciprocity_remainder && !pool.empty() && !(p_rest >= threshold)) {
        screen.reciprocity_remainder = p_rest;
        flagged.insert(flagged.end(), pool.begin(), pool.end());
    }
}

bool has_mass(const Side& sampled, const Side& f) { return !(sampled.sum == 0.0 && f.sum == 0.0); }

/// The screen: each comparison whose p is below kScreenAlpha over the cells
/// gets its references (the remainder's: those of all its cells) replaced by
/// fresh ones kRetestFactor times larger, for that comparison only: the
/// weights' in `ref`, reciprocity's in `reciprocity_ref` (a copy of the first
/// reference where reciprocity did not flag the cell). A fresh reference that
/// replaced one for another comparison's flag would be selected: on a
/// one-way f, reciprocity flags the cells whose f(wo, wi) estimate is high,
/// and the weights' reference left there would be biased low. Every
/// evaluation made, replaced or not, is counted in the screen's tallies.
Screen retest(const BsdfCase& bsdf, const CheckContext& ctx, const std::vector<int>& sides,
              const std::vector<Side>& sampled, const Plan& plan, std::vector<Reference>& ref,
              std::vector<Reference>& reciprocity_ref) {
    Screen screen;
    screen.cell.assign(ref.size(), NAN);
    std::vector<std::size_t> flagged, pool, flagged_reciprocity;
    const double threshold = kScreenAlpha / static_cast<double>(ref.size());
    Side rest_s, rest_f;
    for (std::size_t c = 0; c < ref.size(); ++c) {
        if (!has_mass(sampled[c], ref[c].f)) continue;
        if (!plan.alone[c]) {
            rest_s.add(sampled[c]), rest_f.add(ref[c].f), pool.push_back(c);
            continue;
        }
        const double p = compare(sampled[c], ref[c].f).p;
        if (!(p >= threshold)) screen.cell[c] = p, flagged.push_back(c);
    }
    const double p_rest = compare(rest_s, rest_f).p;
    if (plan.remainder && !pool.empty() && !(p_rest >= threshold)) {
        screen.remainder = p_rest;
        flagged.insert(flagged.end(), pool.begin(), pool.end());
    }
    if (bsdf.claims().reciprocal) screen_reciprocity(ref, plan, threshold, screen, flagged_reciprocity);
    std::vector<std::size_t> fresh_cells = flagged;
    fresh_cells.insert(fresh_cells.end(), flagged_reciprocity.begin(), flagged_reciprocity.end());
    std::sort(fresh_cells.begin(), fresh_cells.end());
    fresh_cells.erase(std::unique(fresh_cells.begin(), fresh_cells.end()), fresh_cells.end());
    std::vector<Reference> fresh(fresh_cells.size());
    ctx.parallel_for(fresh_cells.size(), [&](std::size_t k) {
        const std::size_t c = fresh_cells[k];
        fresh[k] = integrate_cell(bsdf, ctx, sides, c, ref[c].evaluations * kRetestFactor, kRetestChunks + c);
    });
    for (const Reference& r : ref) screen.evaluations += r.evaluations, screen.bad_values += r.bad_values;
    for (const Reference& r : fresh) screen.evaluations += r.evaluations, screen.bad_values += r.bad_values;
    reciprocity_ref = ref;
    const auto fresh_of = [&](std::size_t c) {
        return fresh[static_cast<std::size_t>(std::lower_bound(fresh_cells.begin(), fresh_cells.end(), c) -
                                              fresh_cells.begin())];
    };
    for (const std::size_t c : flagged) ref[c] = fresh_of(c);
    for (const std::size_t c : flagged_reciprocity) reciprocity_ref[c] = fresh_of(c);
    return screen;
}

Outcome judge_cells(const std::vector<Side>& sampled, const std::vector<Reference>& ref, const Plan& plan,
                    const Screen& screen) {
    Outcome o;
    Side rest_s, rest_f, all_s, all_f;
    std::vector<std::size_t> pooled;
    for (std::size_t c = 0; c < sampled.size(); ++c) {
        all_s.add(sampled[c]);
        all_f.add(ref[c].f);
        o.pdf_integral += ref[c].pdf;
        if (!has_mass(sampled[c], ref[c].f)) continue;
        if (plan.alone[c]) {
            o.cells.push_back(compare(sampled[c], ref[c].f));
            if (!std::isnan(screen.cell[c])) {  // retested: it fails only where both references say so
                o.cells.back().p = std::max(o.cells.back().p, screen.cell[c]);
                ++o.retested;
            }
            if (o.heaviest < 0 || o.cells.back().sampled > o.cells[static_cast<std::size_t>(o.heaviest)].sampled)
                o.heaviest = static_cast<int>(o.cells.size()) - 1;
            continue;
        }
        rest_s.add(sampled[c]);
        rest_f.add(ref[c].f);
        ++o.pooled;
    }
    o.total = compare(all_s, all_f);
    o.evaluations = screen.evaluations;
    o.bad_f_values = screen.bad_values;

    if (o.pooled > 0) {
        o.remainder = compare(rest_s, rest_f);
        o.remainder_judged = plan.remainder;
        if (!std::isnan(screen.remainder)) o.remainder.p = std::max(o.remainder.p, screen.remainder), ++o.retested;
        if (!o.remainder_judged) {
            o.excused = o.pooled;
            o.excused_weight = all_s.sum > 0.0 ? rest_s.sum / all_s.sum : 0.0;
            o.excused_integral = all_f.sum > 0.0 ? rest_f.sum / all_f.sum : 0.0;
        }
    }
    for (const Comparison& c : o.cells) o.p_values.push_back(c.p);
    if (o.remainder_judged) o.p_values.push_back(o.remainder.p);
    o.p_values.push_back(o.total.p);
    return o;
}

/// The reciprocity comparisons (Plan::reciprocity_alone, the remainder, the
/// total over every cell), their p-values appended to the outcome's.
void judge_reciprocity(const std::vector<Reference>& ref, const Plan& plan, const Screen& screen, Outcome& o) {
    Outcome::Reciprocity& r = o.reciprocity;
    Side rest, all;
    double rest_reverse = 0.0, all_reverse = 0.0;
    for (std::size_t c = 0; c < ref.size(); ++c) {
        all.add(ref[c].asymmetry), all_reverse += ref[c].reverse;
        if (!has_asymmetry_mass(ref[c])) continue;
        if (ref[c].asymmetry_size.sum == 0.0) {
            ++r.exact;
            continue;
        }
        if (plan.reciprocity_alone[c]) {
            r.cells.push_back(compare_reciprocity(ref[c].asymmetry, ref[c].reverse));
            if (!std::isnan(screen.reciprocity_cell[c])) {
                r.cells.back().p = std::max(r.cells.back().p, screen.reciprocity_cell[c]);
                ++r.retested;
            }
            if (r.heaviest < 0 || r.cells.back().integral > r.cells[static_cast<std::size_t>(r.heaviest)].integral)
                r.heaviest = static_cast<int>(r.cells.size()) - 1, r.heaviest_cell = static_cast<int>(c);
            continue;
        }
        rest.add(ref[c].asymmetry), rest_reverse += ref[c].reverse;
        ++r.pooled;
    }
    r.tested = true;
    r.total = compare_reciprocity(all, all_reverse);
    if (r.pooled > 0) {
        r.remainder = compare_reciprocity(rest, rest_reverse);
        r.remainder_judged = plan.reciprocity_remainder;
        if (!std::isnan(screen.reciprocity_remainder))
            r.remainder.p = std::max(r.remainder.p, screen.reciprocity_remainder), ++r.retested;
        if (!r.remainder_judged) {
            r.excused = r.pooled;
            r.excused_share = all_reverse > 0.0 ? rest_reverse / all_reverse : 0.0;
        }
    }
    for (const Comparison& c : r.cells) o.p_values.push_back(c.p);
    if (r.remainder_judged) o.p_values.push_back(r.remainder.p);
    o.p_values.push_back(r.total.p);
}

chi2::MeanTest energy_test(const chi2::Moments& energy) {
    chi2::MeanTest t = chi2::mean_test(energy, 1.0, kEnergyRounding);
    if (!std::isnan(t.p_value)) t.p_value = t.mean > 1.0 ? 0.5 * t.p_value : 1.0;
    return t;
}

/// The largest |z| over the cells judged alone; NaN where any is NaN, so
/// that it never slips through a figure or a message.
double largest_abs_z(const std::vector<Comparison>& cells) {
    double largest = 0.0;
    for (const Comparison& c : cells) largest = std::isnan(c.z) ? c.z : std::max(largest, std::abs(c.z));
    return largest;
}

/// The relative shift of the heaviest cell's mean that its z-test detects
/// with probability 0.9: `shift` standard errors over its integral (NaN where
/// no cell was judged alone).
double heaviest_shift(const std::vector<Comparison>& cells, int heaviest, double shift) {
    if (heaviest < 0) return NAN;
    const Comparison& c = cells[static_cast<std::size_t>(heaviest)];
    return shift * c.standard_error / c.integral;
}

/// Reciprocity's figures; its power: the relative asymmetry of the heaviest
/// cell (by the reverse integral) that its z-test detects with probability 0.9.
void add_reciprocity_figures(CheckResult& r, const Outcome::Reciprocity& o, double shift) {
    const double largest = largest_abs_z(o.cells), heavy = heaviest_shift(o.cells, o.heaviest, shift);
    r.figures.insert(r.figures.end(),
                     {{"reciprocity_tested", o.tested ? 1.0 : 0.0},
                      {"reciprocity_cells_judged", static_cast<double>(o.cells.size())},
                      {"reciprocity_cells_pooled", static_cast<double>(o.pooled)},
                      {"reciprocity_cells_exact", static_cast<double>(o.exact)},
                      {"reciprocity_remainder_judged", o.remainder_judged ? 1.0 : 0.0},
                      {"reciprocity_cells_excused", static_cast<double>(o.excused)},
                      {"reciprocity_excused_share", o.excused_share},
                      {"reciprocity_cells_retested", static_cast<double>(o.retested)},
                      {"reciprocity_largest_abs_z", o.tested ? largest : NAN},
                      {"reciprocity_z_total", o.tested ? o.total.z : NAN},
                      {"power_relative_reciprocity_shift", heavy},
                      {"reciprocity_heaviest_cell", o.heaviest_cell < 0 ? NAN : static_cast<double>(o.heaviest_cell)}});
}

void add_figures(CheckResult& r, const DrawTally& t, const Outcome& o, double level) {
    const double shift = detectable_shift_in_standard_errors(level);
    const double heavy = heaviest_shift(o.cells, o.heaviest, shift);
    r.figures = {{"samples", static_cast<double>(t.draws)},
                 {"mean_continuous_weight", o.total.sampled},
                 {"albedo_continuous", o.total.integral},
                 {"standard_error", o.total.standard_error},
                 {"z_total", o.total.z},
                 {"mean_energy_weight", o.energy.mean},
                 {"energy_t", o.energy.t},
                 {"cells_judged", static_cast<double>(o.cells.size())},
                 {"cells_pooled", static_cast<double>(o.pooled)},
                 {"cells_retested", static_cast<double>(o.retested)},
                 {"remainder_judged", o.remainder_judged ? 1.0 : 0.0},
                 {"cells_excused", static_cast<double>(o.excused)},
                 {"excused_weight_share", o.excused_weight},
                 {"excused_integral_share", o.excused_integral},
                 {"reference_evaluations", static_cast<double>(o.evaluations)},
                 {"mis_pdf_integral", o.pdf_integral},
                 {"bad_weights", static_cast<double>(t.bad_weight)},
                 {"bad_directions", static_cast<double>(t.bad_direction)},
                 {"off_side_samples", static_cast<double>(t.off_side)},
                 {"mis_pdf_zero_samples", static_cast<double>(t.pdf_zero)},
                 {"tests", static_cast<double>(o.p_values.size())},
                 {"power_relative_albedo_shift", shift * o.total.standard_error / o.total.integral},
                 {"power_relative_heaviest_cell_shift", heavy},
                 {"power_level", level},
                 {"f_bad_values", static_cast<double>(o.bad_f_values)}};
    add_reciprocity_figures(r, o.reciprocity, shift);
}

void judge(CheckResult& r, const DrawTally& t, const Outcome& o) {
    r.p_value = chi2::sidak_min_p(o.p_values);
    r.verdict = Verdict::Pass;
    r.summary = fmt::format("mean weight {:.6g} vs integral of f |cos| {:.6g} (z = {:.2f}); {} cells judged", o.total.sampled,
                            o.total.integral, o.total.z, o.cells.size());
    const double worst = largest_abs_z(o.cells);
    r.message = fmt::format("in expectation: the continuous weights' mean {:.9g} against the integral of f |cos| "
                            "{:.9g} ({:.2f} standard errors); per cell, the largest |z| {:.2f} over {} cells judged "
                            "alone, {} pooled ({}), {} excused (share {:.3g} of the weight, {:.3g} of the integral); "
                            "energy: mean energy weight {:.9g} ({:.2f} standard errors above 1); integral of the MIS "
                            "pdf {:.6g} (stated)",
                            o.total.sampled, o.total.integral, o.total.z, worst, o.cells.size(), o.pooled,
                            o.remainder_judged ? fmt::format("z = {:.2f}", o.remainder.z) : "not judged", o.excused,
                            o.excused_weight, o.excused_integral, o.energy.mean, o.energy.t, o.pdf_integral);
    const Outcome::Reciprocity& rec = o.reciprocity;
    if (rec.tested) {
        const double largest = largest_abs_z(rec.cells);
        r.message += fmt::format("; reciprocity in expectation (f(wo, wi) s - f(wi, wo) per cell, paired, within "
                                 "{:.3g} of f(wi, wo)'s integral): the largest |z| {:.2f} over {} cells judged alone, "
                                 "{} exact (every difference 0), {} pooled ({}), {} excused (share {:.3g} of f(wi, wo)'s integral), over the sphere "
                                 "z = {:.2f}",
                                 kReciprocityTolerance, largest, rec.cells.size(), rec.exact, rec.pooled,
                                 rec.remainder_judged ? fmt::format("z = {:.2f}", rec.remainder.z) : "not judged",
                                 rec.excused, rec.excused_share, rec.total.z);
        r.summary += fmt::format("; reciprocity max |z| {:.2f} over {} cells", largest, rec.cells.size());
    } else {
        r.message += "; reciprocity: not claimed, not tested";
    }
    if (o.bad_f_values > 0) {
        r.verdict = Verdict::Fail;
        r.summary = fmt::format("{} evaluations of f not finite or negative", o.bad_f_values);
        r.message = fmt::format("{} of the reference's evaluations of f(wo, wi){} are not finite or negative. ",
                                o.bad_f_values, rec.tested ? " and f(wi, wo)" : "") +
                    r.message;
    }
    const uint64_t exact = t.bad_weight + t.bad_direction + t.off_side + t.pdf_zero;
    if (exact > 0) {
        r.verdict = Verdict::Fail;
        r.summary = fmt::format("{} samples break an exact rule: {}", exact, t.first_problem);
        r.message = fmt::format("{} weights not finite or negative, {} directions not unit, {} on an unclaimed side, {} "
                                "where pdf(wo, wi) is not positive (MIS weights would not sum to 1); first: {}. ",
                                t.bad_weight, t.bad_direction, t.off_side, t.pdf_zero, t.first_problem) +
                    r.message;
    }
}

class BsdfExpectationCheck final : public BsdfCheck {
public:
    std::string name() const override { return "bsdf_expectation"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"bad_weights", "draws whose weight is not finite or negative", FigureRule::Zero},
                            {"bad_directions", "draws whose wi is not a unit vector", FigureRule::Zero},
                            {"off_side_samples", "continuous draws on a side the lobes do not claim", FigureRule::Zero},
                            {"mis_pdf_zero_samples", "continuous draws where pdf(wo, wi) is not positive",
                             FigureRule::Zero},
                            {"cells_pooled", "cells pooled into the remainder (pilots promised too few terms)",
                             FigureRule::Counted},
                            {"cells_retested", "comparisons retested against a 16 times larger reference",
                             FigureRule::Counted},
                            {"cells_excused", "cells excused (their remainder too sparse to judge)", FigureRule::Counted},
                            {"f_bad_values", "evaluations of f not finite or negative", FigureRule::Zero},
                            {"reciprocity_cells_pooled", "reciprocity: cells pooled into the remainder",
                             FigureRule::Counted},
                            {"reciprocity_cells_retested", "reciprocity: comparisons retested", FigureRule::Counted},
                            {"reciprocity_cells_excused", "reciprocity: cells excused (their remainder too sparse)",
                             FigureRule::Counted}},
                .p_value = "p-value: the smallest of the cells', remainder's, total's, reciprocity's and energy's, "
                           "\u0160id\u00e1k-corrected"};
    }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "A stochastic BSDF in expectation: the sampled weights that land in each cell of the sphere "
                "against the integral of its estimated f |cos| over the cell (z-tests with both sides' measured "
                "variances; cells judged alone where pilots promise 50 effective terms, the others pooled), the "
                "total, energy at most 1, the MIS pdf positive at every sampled direction, and where the case claims "
                "reciprocity, f(wo, wi) s against f(wi, wo) per cell in expectation (paired at the same directions).",
                "1 \u2212 (1 \u2212 min p)^k, \u0160id\u00e1k over the k comparisons; a retested one's p is the "
                "larger of its two."};
    }
    std::string description() const override {
        return "stochastic BSDF: sampled weights per cell of the sphere against the integral of its estimated f "
               "|cos| (z-tests, Sidak), reciprocity in expectation where claimed, energy at most 1, the MIS pdf "
               "positive where it samples";
    }

protected:
    Applicability bsdf_applicability(const BsdfCase& b) const override {
        // A deterministic f is bsdf_chi2's, bsdf_weight's and bsdf_albedo's to test, exactly.
        return Applicability::when(b.claims().stochastic && has(b.claims().lobes, BsdfFlags::Continuous));
    }

    CheckResult run_bsdf(const BsdfCase& bsdf, const CheckContext& ctx) const override {
        const std::vector<int> sides = sides_of(bsdf);
        const DrawTally t = draw(bsdf, ctx, sides);
        const uint64_t pilot_count = std::max<uint64_t>(1000, ctx.options().samples / 8);
        const DrawTally pilot_tally = pilot_draws(bsdf, ctx, sides, static_cast<std::size_t>(pilot_count));
        const std::vector<Side> sampled = sampled_sides(t, &pilot_tally), pilot = sampled_sides(pilot_tally);
        std::vector<Reference> ref = reference(bsdf, ctx, sides, pilot, 1.0, kReferenceChunks);
        const Plan plan = plan_from_pilots(pilot, static_cast<double>(t.draws) / static_cast<double>(pilot_count),
                                           reference(bsdf, ctx, sides, pilot, kPilotShare, kPilotReferenceChunks), ref);
        std::vector<Reference> reciprocity_ref;
        const Screen screen = retest(bsdf, ctx, sides, sampled, plan, ref, reciprocity_ref);
        Outcome o = judge_cells(sampled, ref, plan, screen);
        if (bsdf.claims().reciprocal) judge_reciprocity(reciprocity_ref, plan, screen, o);
        o.energy = energy_test(t.energy);
        o.p_values.push_back(o.energy.p_value);
        CheckResult r;
        r.samples = t.draws;
        add_figures(r, t, o, power_level(ctx.options(), static_cast<int>(o.p_values.size())));
        judge(r, t, o);
        FamilyPoint point = family_point(bsdf, "continuous albedo in expectation against theta_o", "albedo");
        const double half = 2.576 * o.total.standard_error;
        point.values = {{"mean continuous weight (99% interval)", o.total.sampled, o.total.sampled - half,
                         o.total.sampled + half},
                        {"integral of f |cos| (estimated)", o.total.integral},
                        {"mean energy weight", o.energy.mean}};
        point.limits = {{"energy bound", 1.0}};
        r.family_points.push_back(std::move(point));
        return r;
    }
};

}  // namespace expectation_detail

std::unique_ptr<Check> make_bsdf_expectation_check() {
    return std::make_unique<expectation_detail::BsdfExpectationCheck>();
}

}  // namespace warpcheck::bsdf
