// Expected cell probabilities: the density integrated over every cell by
// adaptive Gauss-Kronrod cubature, accurate enough for the sample count in use.
//
// The accuracy rule. With N samples, cell i's count has Poisson standard
// deviation sqrt(E_i), E_i = N P_i. An integration error d in P_i shifts E_i by
// N d; we require N d <= f sqrt(E_i) with f = 1% by default, i.e.
//     d <= f * sqrt(P_i / N)                                 (probability units)
// so that quadrature error moves no Pearson term by more than ~f^2 of its
// typical size. P_i is the current estimate, floored at 1/N (cells expected to
// hold less than one sample are pooled anyway, and their error then counts
// against the pool). The error estimate is Boost's |Kronrod - Gauss| difference,
// which for smooth densities exceeds the true error of the Kronrod value by
// orders of magnitude, so the rule is met with margin.
//
// The rule: the 15-point Gauss-Kronrod nodes and weights of Boost.Math (with the
// embedded 7-point Gauss rule) as a tensor product on each parameter rectangle.
// Whole rectangles are evaluated in one batch call of the density, so a warp's
// virtual pdf is paid per 225 points, not per point. A rectangle whose error
// estimate is too large is split in half across the parameter whose Gauss
// substitution changed the result most (so a sharp peak draws refinement where
// it is), globally adaptive per cell (largest error first).
//
// The error bound is a claim to verify, not a given. Gauss and Kronrod share
// their nodes' symmetry: a jump along a cell's diagonal puts nodes exactly on
// it, where both rules agree and both are wrong (a triangle's hypotenuse
// x + y = 1 through the cells' corners: bound 500 times too small), and a
// narrow peak can fall between the nodes of both. With `verify`, every cell is
// integrated again on a split at irrational fractions of its sides, whose nodes
// share no symmetry with the first rule's; where the two disagree by more than
// both bounds together, a third split arbitrates (the median is kept) and the
// cell's bound becomes the largest disagreement plus the largest bound.
//
// The float noise of a density. A warp's pdf is a float function of float
// arguments: its value at a float point stands for the density over that
// float's rounding interval only to within its change over one float step of
// each argument (an intermediate rounded at the argument's scale, such as
// 1 + g^2 against 2 g cos theta in Henyey-Greenstein's textbook form, errs by
// at most that much). With `float_noise`, each cell carries the integral of
// that change over its final regions (3-point Gauss nodes per parameter; each
// argument moved one float up and down, the larger change of the two, so that
// a float staircase counts its step; summed over the arguments, since the
// roundings of a dot product's terms add up). A change of more than half the
// density is a jump (a node on a support's edge), not rounding, and is not
// counted there; instead, each final region whose values span more than a
// factor 2 adds a bound on the mass within one float step of a jump across it
// (RegionRule::jump_band): float points on either side of a jump stand for
// half a step beyond it, which a tiny support (a sun, a sliver of light)
// feels at 1e-3.
#pragma once

#include <cstddef>
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "chi2/binning.h"
#include "chi2/domain.h"
#include "chi2/parallel.h"

namespace warpcheck::chi2 {

/// Density callback: densities[i] = pdf(points[i]), with respect to the domain's
/// measure (length, area, solid angle). Called from several threads at once
/// when the ParallelFor is parallel.
using BatchPdf = std::function<void(std::span<const DomainPoint> points, std::span<double> densities)>;

struct QuadratureOptions {
    uint64_t sample_count = 1'000'000;  ///< N of the accuracy rule
    double accuracy_fraction = 0.01;    ///< f of the accuracy rule
    std::size_t max_regions_per_cell = 1024;  ///< refinement budget of one cell
    bool verify = false;       ///< integrate each cell again on an irrational split (see the top)
    bool float_noise = false;  ///< estimate each cell's float noise of the density (see the top)
};

/// The accuracy rule's absolute error allowance for a cell of probability p.
double cell_tolerance(double probability, const QuadratureOptions& options);

struct CellIntegrals {
    std::vector<double> probability;  ///< per cell: the density's integral over it
    std::vector<double> error;        ///< per cell: the estimated absolute error (verified, with `verify`)
    /// Per cell (with `float_noise`): the integral of the density's change over
    /// one float step of its arguments; empty otherwise.
    std::vector<double> float_noise;
    double total = 0.0;               ///< sum of probability (cell order)
    double error_total = 0.0;         ///< sum of error
    double float_noise_total = 0.0;   ///< sum of float_noise
    /// Cells whose second integration disagreed with the first by more than
    /// both bounds (with `verify`): their bound was widened to cover it.
    std::size_t verification_mismatches = 0;
    std::size_t unconverged_cells = 0;  ///< cells that ran out of refinement budget
    double worst_error_ratio = 0.0;   ///< max over cells of error / tolerance (<= 1: rule met)
    uint64_t evaluations = 0;         ///< density evaluations
    uint64_t negative_values = 0;     ///< nodes where the density was negative
    uint64_t nonfinite_values = 0;    ///< nodes where the density was NaN or infinite
};

/// Integrates `pdf` over every cell of `binning`. Work is split by cell, so the
/// result does not depend on the executor.
CellIntegrals integrate_cells(const Binning& binning, const BatchPdf& pdf, const QuadratureOptions& options,
                              const ParallelFor& parallel_for = serial_for);

/// The same over any rectangles of `binning`'s parameter space, each as one
/// cell (results in the rectangles' order): pieces of cells, e.g. the refined
/// strips of a marginal CDF (chi2/marginal_cdf.h).
CellIntegrals integrate_rects(const Binning& binning, std::span<const ParamRect> rects, const BatchPdf& pdf,
                              const QuadratureOptions& options, const ParallelFor& parallel_for = serial_for);

/// One cell integrated again around points where the density is known to be
/// positive (samples that landed in a cell the cubature integrated as zero: a
/// sliver of support between its nodes). A piece that holds such points and
/// integrates to zero is cut into 3 x 3 pieces at the points' range widened by
/// its own width, and each piece is treated the same way (16 levels at most),
/// so a sliver narrow in either parameter gets pieces of its own scale; the
/// other pieces are integrated as usual.
struct GuidedIntegral {
    double value = 0.0, error = 0.0, float_noise = 0.0;
    uint64_t evaluations = 0;
    std::size_t pieces = 0;  ///< integrate_partitioned: the pieces integrated
};
GuidedIntegral integrate_around(const Binning& binning, const ParamRect& cell,
                                std::span<const std::array<double, 2>> points, const BatchPdf& pdf,
                                const QuadratureOptions& options);

/// A pilot's cluster narrower than the rule's nodes. The 15-point rule on a
/// cell puts its nodes ~1/15 of the side apart (closer near the ends), so a
/// spot or sliver of the density a few hundred times narrower than the cell
/// (glass of eta 1.001 refracting a grazing wo into a 5e-5 rad spot; an
/// anisotropic conductor of alpha 1e-3 x 1, whose lobe is a sheet) can lie
/// between all of them and those of the verifying split alike: both agree on
/// a value that leaves its mass out, and the bound is as small as they are
/// wrong. A pilot drawn from the sampler (chi2/equal_probability.h) shows
/// where the mass is. Along each parameter, a run of kMinPilotCluster or more
/// of a cell's pilot points, each within 1 / kPilotClusterDensity of an even
/// spread's spacing of the next, is a cluster: the cell is cut around it (its
/// extent widened by itself each way, for its tails) where that keeps under
/// half the side, and each piece is treated the same way (16 cuts at most),
/// so a cluster ends in a piece of its own scale, which the rule's nodes see;
/// the pieces are integrated as usual (verified, with their float noise).
/// 16: spacings of points spread evenly are exponential, so 7 in a row under
/// a sixteenth of their mean has probability ~(1/16)^7 ~ 4e-9 per run. A
/// density can vary that much across a cell in the tail of a peaked lobe
/// (rough_conductor alpha 0.05 at theta_o 60 has 137 such cells): a cut that
/// was not needed costs evaluations only (the three checks' cubature in
/// `validate --all`: 298 M -> 492 M), since a value changes only where the
/// pieces disagree with the first beyond both bounds.
inline constexpr double kPilotClusterDensity = 16.0;
/// A cluster at the edge of a cell, or two clusters apart, with too few
/// points for a run (glass of eta 1.001: 2 of a cell's 64 pilot points in
/// the refracted spot at its lower edge, the rest 1e-2 away above the
/// horizon) leaves a gap: where the widest empty stretch between a cell's
/// points (its ends counting as points) exceeds this share of a side, the
/// cell is cut an eighth of the gap away from the points on each side (no
/// nearer than a float step of a sample, which stands for its interval). A
/// quarter: the widest gap between 64 points spread evenly is ~ln(64)/64 =
/// 6.5% of the side (a quarter has probability ~1e-6 there).
inline constexpr double kPilotGapShare = 0.25;
/// A whole cell is cut at a gap only where its n pilot points, spread
/// evenly, would leave so wide a gap with at most this chance: the share s
/// of a side with (n + 1) (1 - s)^n = kPilotGapChance (the union bound over
/// the n + 1 spacings), or kPilotGapShare if that is wider. 1e-6: the
/// chance the quarter was chosen for at 64 points (s = 0.245 there), now
/// held at every n. A cell of 16 points (a quarter of the mean, in the tail
/// of a lobe) left a quarter of a side empty by chance in one cell of six,
/// and each such cut cost a cell's cubature twice over (cosine_hemisphere:
/// 54 of 1024 cells cut, none of them changed); with 16 points it now takes
/// 65% of the side. Pieces of a cell already cut keep kPilotGapShare: there
/// a cluster was found, and the cuts narrow towards it.
inline constexpr double kPilotGapChance = 1e-6;
/// The gap share that cuts a whole cell of n pilot points (kPilotGapChance).
double pilot_gap_share(std::size_t n);
/// A cell with fewer pilot points than this is not cut, nor is a run of
/// fewer a cluster: too few to tell one from a tail's stragglers, whose cuts
/// only cost evaluations (a smaller run, under ~13% of a cell of ~64 pilot
/// points, is left to the rule: mass it misses there still counts against
/// the sampler). Once a cell is cut, its pieces go on narrowing at a gap
/// while they hold 2 points (a spot of 2 points at a cell's edge).
inline constexpr std::size_t kMinPilotCluster = 8;

/// Whether `points` (parameters, inside `cell`) form a cluster that
/// integrate_partitioned cuts around.
bool needs_pilot_partition(const Binning& binning, const ParamRect& cell, std::span<const std::array<double, 2>> points);

/// One cell integrated on the partition that its pilot points place (see
/// kPilotClusterDensity); the pieces' values, bounds and float noise summed.
GuidedIntegral integrate_partitioned(const Binning& binning, const ParamRect& cell,
                                     std::span<const std::array<double, 2>> points, const BatchPdf& pdf,
                                     const QuadratureOptions& options);

}  // namespace warpcheck::chi2
