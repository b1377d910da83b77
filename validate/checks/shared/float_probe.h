// A sample's float neighbourhood in its domain's coordinates: the points a
// few float spacings away that a correct float warp's rounding could equally
// have produced. Checks that find a sample where its density (or the value
// returned with it) disagrees with the functions at x ask whether they agree
// at one of these (a support's edge, a pixel's border, a light's silhouette),
// and count such samples against one bound: consistency, sample_pdf and
// light_radiance hold them to the same rule.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "validate/api/warp_case.h"

namespace warpcheck {

/// How far a value a sampler returns (its pdf, its weight) may be from the
/// same value recomputed by its function at the rounded sample, relative:
/// 2^-12 (4096 float ulps). The two sides compute in float along different
/// paths (from u, and again from the rounded x), and a density's logarithmic
/// slope (hundreds for a sharp power-cosine lobe, ~4 / alpha per radian for
/// Trowbridge-Reitz) multiplies x's few ulps of rounding to ~1e-5, while a
/// wrong factor (a selection probability, a Jacobian, a missing cosine) is off
/// by percent. Below FLT_MIN both sides are denormal floats with no relative
/// precision, so absolute differences up to FLT_MIN are accepted. sample_pdf,
/// weight, bsdf_weight and mis_weights hold values to it.
inline constexpr double kReturnedValueTolerance = 0x1p-12;

/// What counts as a discontinuity for the edge band (EdgeBand) of a value
/// that is not a pdf's support: a change of more than 2^-6 relative within
/// kProbeUlps float steps. 64 times the 2^-12 a returned value is held to, so
/// a value's float noise (which can exceed 2^-12 where it is steep) does not
/// pass for a band of jumps and widen the bound for its own errors, while a
/// silhouette (L or pdf to 0) or a pixel's border (a factor) is one.
inline constexpr double kJumpTolerance = 0x1p-6;

/// How far a zero-pdf sample's neighbours are probed: kProbeUlps float
/// spacings at the domain's extent (Domain::slack's scale) in each coordinate.
/// A float warp computes a coordinate from terms as large as the domain (a
/// lerp over it, (bucket + du) / n) in a handful of roundings of half such a
/// spacing each, so 4 is the error of about eight of them; a sample a wrong
/// warp puts where its pdf is 0 lies, but for a set of vanishing measure,
/// further from any positive pdf.
inline constexpr int kProbeUlps = 4;
/// The per-sample rate of samples a correct warp rounds across its support's
/// edge, for the count bound: only samples whose exact value lies within a
/// few spacings of an edge can be rounded across it, a band that holds about
/// 2^-24 of the samples per spacing along an edge that is the image of a line
/// of inputs (2^-24 is the largest input spacing). 2^-16 allows 256 such
/// line-spacings, a table with dozens of boundaries between empty and full
/// rows, while a warp that puts mass on an edge itself (clamping onto it)
/// puts a fixed fraction of its samples there. 15 per 10^6 samples.
inline constexpr double kRoundedAcrossEdgeRate = 0x1p-16;
/// The chance that a correct warp's count exceeds the bound (the round trip's
/// other-preimage bound uses the same): far below any run's level.
inline constexpr double kConsistencyBoundTail = 1e-9;
/// The probe's step in each coordinate: the float spacing just below the
/// domain's extent, the largest a coordinate inside it has (or at the
/// coordinate itself, where that is larger: unbounded lines).
std::array<float, 3> probe_steps(const chi2::Domain& domain, const WarpOutput& x);

/// The points probed around x: 1 to kProbeUlps steps along each of the
/// 3^d - 1 sign directions of its d coordinates.
std::vector<WarpOutput> probe_points(const chi2::Domain& domain, const WarpOutput& x);

/// How far the neighbours of a direction lie that measure the float
/// resolution of a value computed at it (a BSDF's f or pdf, a light's edge): 2^-20, 8 float ulps of a unit vector's components.
inline constexpr double kFloatStep = 0x1p-20;
/// How many neighbours float_neighbours gives.
inline constexpr std::size_t kFloatNeighbours = 8;

/// The kFloatNeighbours directions `step` from w in eight directions of
/// its tangent plane, renormalised and rounded to float. What f or pdf does
/// over them (a smooth change plus each evaluation's own rounding) is the
/// float resolution of a value computed at w: a half vector recomputed from
/// rounded directions, a Fresnel term near the critical angle, a microfacet
/// seen edge-on.
std::vector<WarpOutput> float_neighbours(const WarpOutput& w, double step = kFloatStep);

/// The probe points of several samples gathered into one batch, so that a
/// case's functions are called once for them all (a Python case pays per
/// call, and a wrong one has a probe at every sample): sample k's points are
/// points[start[k], start[k + 1]).
struct ProbeBatch {
    std::vector<WarpOutput> points;
    std::vector<std::size_t> start{0};
    void add(const std::vector<WarpOutput>& p) {
        points.insert(points.end(), p.begin(), p.end());
        start.push_back(points.size());
    }
    /// Whether `test` holds at any point of sample k (its index in points).
    template <typename Test>
    bool any(std::size_t k, Test test) const {
        for (std::size_t j = start[k]; j < start[k + 1]; ++j)
            if (test(j)) return true;
        return false;
    }
};

/// For each of the samples `which` (indices i), whether `holds(i, values, j)`
/// is true at any of its probe points j, where `points_of(i)` gives sample
/// i's probes and `values = evaluate(points)` is the case evaluated at all of
/// them in one call (never with none: a sample with no probes holds nowhere).
/// The probes of consistency, sample_pdf, weight, light_radiance and
/// mis_weights all take this shape.
template <typename PointsOf, typename Evaluate, typename Holds>
std::vector<unsigned char> holds_at_a_probe(std::span<const std::size_t> which, PointsOf&& points_of,
                                            Evaluate&& evaluate, Holds&& holds) {
    ProbeBatch probes;
    for (const std::size_t i : which) probes.add(points_of(i));
    std::vector<unsigned char> out(which.size(), 0);
    if (probes.points.empty()) return out;  // no call with nothing to evaluate
    const auto values = evaluate(std::span<const WarpOutput>(probes.points));
    for (std::size_t k = 0; k < which.size(); ++k)
        out[k] = probes.any(k, [&](std::size_t j) { return holds(which[k], values, j); });
    return out;
}

/// Random samples probed for a discontinuity nearby (EdgeBand): about 2^14
/// of them, every k-th for k = samples / 2^14 clamped to [1, 64]. 2^14
/// probes see a share of 10^-3 16 times; fewer samples are all probed (at
/// 2 x 10^4, a band of 10^-3 seen 20 times, where every 16th saw it about
/// once); at 10^6 a probe costs 2d / 61 extra evaluations a sample.
inline std::size_t edge_band_stride(uint64_t samples) {
    return static_cast<std::size_t>(std::clamp<uint64_t>(samples >> 14, 1, 64));
}

/// The share of random samples that lie within kProbeUlps spacings of a
/// discontinuity of what a check compares, measured on every
/// edge_band_stride-th: only those can be rounded across it. The fixed rate
/// kRoundedAcrossEdgeRate covers edges that are images of lines of inputs;
/// a support that is thin in some direction has far more of its samples
/// that close to an edge (a ring 1e-4 wide: 5e-3 of them; a sphere light of
/// angular radius 1e-4: about 4e-3), and the bound then uses the measured
/// share. consistency probes for a zero pdf; sample_pdf,
/// weight and light_radiance for a value that jumps beyond kJumpTolerance;
/// mis_weights for a jump of any strategy's own or MIS pdf.
struct EdgeBand {
    uint64_t probed = 0;  ///< random samples probed
    uint64_t near = 0;    ///< of those, within kProbeUlps of a discontinuity
    void add(bool is_near) {
        ++probed;
        near += is_near ? 1 : 0;
    }
    void merge(const EdgeBand& o) {
        probed += o.probed;
        near += o.near;
    }
    /// The measured share bounded above: (sqrt(k + 1) + 3.5)^2 / probed for
    /// k near, above the exact Poisson upper limit at tail 1e-9 (about 24 at
    /// k = 1, 27 at 2, 54 at 16; the formula gives 24.1, 27.4, 58.1); 0 when
    /// none was near (the fixed rate then stands alone).
    double share() const;
};

/// The points kProbeUlps spacings (probe_steps) from x along each coordinate,
/// both ways, that lie in the domain without the slack at its boundary (a
/// zero just beyond the domain is not a discontinuity of the support) but
/// with the slack on a direction's length (a step along one coordinate moves
/// a unit vector off the sphere by up to kProbeUlps spacings).
std::vector<WarpOutput> axis_probes(const chi2::Domain& domain, const WarpOutput& x);

/// The inputs that approach u from inside the unit square or interval:
/// u moved towards its centre by 2^-24, 2^-21, ..., 2^-3 in each coordinate,
/// in that order (empty for raw bits and for a BSDF's three uniforms, whose
/// first picks a lobe). A sample that fails its check and that no float
/// neighbour excuses may still lie on its support's closure below float
/// resolution (a light's corner seen at a grazing angle is thinner than a
/// float direction for a distance of 10^-2 of the light): it does if the
/// samples of these inputs converge to it and pass the check further out
/// (excused_in_the_limit). Only for edge inputs, which map onto a support's edges
/// and corners by design: a sampler that maps one to a wrong place (a
/// default direction, a clamp past the support) has samples nearby that do
/// not converge to it, while a sampler that overshoots its support
/// continuously would pass this test, and its random samples catch it.
std::vector<WarpInput> inward_ladder(const WarpInput& u, InputKind kind);

/// Whether x, the sample of an edge input u that failed its check, is the
/// limit of the samples `ladder` of inward_ladder(u) (nearest first), and
/// they show the support around it: every one finite; their distances from
/// x never growing as the step shrinks (beyond kProbeUlps float steps); the
/// nearest within kProbeUlps float steps of x or at most half the next one's
/// distance (a square-root warp closes to 0.35 per step of 8, a linear one
/// to 0.125; a jump of any size keeps its distance, about 1); and the
/// farthest step passes the check (passes[k]: the caller's rule at
/// ladder[k]; nearer steps may fail as x does, rounded across a support
/// thinner than a float step). So x lies where continuous
/// paths of correct samples end, below the float resolution of its support.
bool excused_in_the_limit(const chi2::Domain& domain, const WarpOutput& x, std::span<const WarpOutput> ladder,
                          std::span<const unsigned char> passes);

/// How many random samples may be excused by their neighbourhood: a Poisson
/// bound, with tail kConsistencyBoundTail, at the larger of
/// kRoundedAcrossEdgeRate and the measured share of samples near a
/// discontinuity per random sample.
uint64_t rounded_across_edge_bound(uint64_t random_samples, const EdgeBand& band = {});

}  // namespace warpcheck
