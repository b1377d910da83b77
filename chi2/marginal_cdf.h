// The CDF of one parameter of a domain (x or y of a box, phi or r^2 of the
// disk, phi or cos theta of a spherical cap, the line's parameter of a 1D
// domain), tabulated from a density by the engine's cubature: the domain is cut
// into strips across that parameter (a Binning with one cell across the other
// parameter), each strip integrated (chi2/quadrature.h), and the cumulative sums
// interpolated linearly in between.
//
// Accuracy: two error sources, both reported. The cubature's own error bound
// (summed over strips: the worst case for the CDF at any point), and the linear
// interpolation between strip edges, estimated from the interpolation error of
// the grid with every other edge (measured exactly at the left-out edges) by
// the h^2 law of linear interpolation, and measured inside every 16th strip
// (a probe at 0.2, 0.38, 0.5, 0.62 or 0.8 of it, in turn), which sees structure within
// strips that leaves neighbouring strips equal. Both are set far
// below the 1/sqrt(N) resolution of the unbinned tests (see unbinned_check).
//
// Peaks: where the density is peaked within a few strips (a sharp specular
// lobe's cos theta, a steep exponential), the interpolation error of the
// uniform strips is large. With a CdfRefinement, each pair of sibling strips
// whose estimate exceeds the target is split into two pairs of half the width
// (the h^2 law: a quarter of the error), again and again where needed, within
// a budget of strips. A strip can also be cut across the other parameter into
// rows integrated apart (at the other marginal's quantiles), so that a peak
// narrow in that parameter gets rows of its own instead of falling between
// the cubature's first nodes across the whole strip.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "chi2/binning.h"
#include "chi2/domain.h"
#include "chi2/parallel.h"
#include "chi2/quadrature.h"

namespace warpcheck::chi2 {

/// A probe sees one point of its strip; the interpolation error stated from
/// the probes is this times the largest seen. The probes see at least 0.94
/// of a smooth density's largest error within a strip (a probe at 0.38 of
/// it), and at least 0.8 of it on the alternating densities of
/// tests/chi2/test_marginal_cdf.cpp (2 to 8 bins per strip): 2 covers both
/// with room.
inline constexpr double kProbeMargin = 2.0;

struct MarginalCdf {
    int axis = 0;                    ///< 0: the binning's u parameter, 1: its v parameter
    std::vector<double> edges;       ///< strip edges in the parameter, ascending (refined strips included)
    /// Per strip of the uniform grid (and one past the end): the index in
    /// `edges` of its first edge; its refined strips lie up to the next one's.
    std::vector<std::size_t> first_edge;
    std::vector<double> cdf;         ///< the normalised CDF at the edges: 0 ... 1
    double total = 0.0;              ///< the density's integral over the domain (before normalising)
    double quadrature_error = 0.0;   ///< sum of the strips' error estimates, relative to total
    double interpolation_error = 0.0;  ///< estimated max error of the linear interpolation
    /// The largest interpolation error measured inside probed strips (already
    /// in interpolation_error, times kProbeMargin).
    double probed_interpolation_error = 0.0;
    std::size_t unconverged_strips = 0;
    std::size_t refined_strips = 0;  ///< strips beyond the uniform grid's, from refinement
    uint64_t evaluations = 0;
    uint64_t bad_values = 0;         ///< negative or non-finite density values met

    /// Bound on |tabulated CDF - true CDF| anywhere: both sources added.
    double error_bound() const { return quadrature_error + interpolation_error; }
    /// The CDF at parameter t (0 below the first edge, 1 above the last).
    double operator()(double t) const;
    /// The CDF at t and at lo <= t <= hi, each the value operator() gives,
    /// finding t's strip once: ends within it are interpolated there.
    struct AtBand {
        double lo = 0.0, value = 0.0, hi = 0.0;
    };
    AtBand at_band(double lo, double t, double hi) const;
    /// Indexes `edges` for the lookups of operator() and at_band (the same
    /// strips, found faster): tabulate_marginal_cdf calls it; call it again
    /// after changing `edges` by hand.
    void index_strips();

private:
    /// The strip (index into edges) that holds t, edges.front() < t < edges.back().
    std::size_t strip_of(double t) const;
    /// strip_of by the uniform grid and its refined strips (no index needed).
    std::size_t strip_by_grid(double t) const;
    /// Per bucket of kBucketsPerStrip * strips equal buckets across the edges'
    /// range, and one past the end: the strip that holds the bucket's start.
    /// Empty when the edges are not finite and ascending (strip_by_grid then).
    std::vector<uint32_t> bucket_strip_;
    double bucket_scale_ = 0.0;  ///< buckets per unit of the parameter
    double interpolate(std::size_t j, double t) const {
        const double w = (t - edges[j]) / (edges[j + 1] - edges[j]);
        return cdf[j] + w * (cdf[j + 1] - cdf[j]);
    }
};

// Inline: the unbinned check looks up a million samples per marginal.
inline std::size_t MarginalCdf::strip_of(double t) const {
    // The largest j < strips with edges[j] <= t. The index's bucket of t names
    // the strips that hold its start and its end; where t lies between their
    // edges, as it does unless rounding put t in a neighbouring bucket, the
    // answer is among them. Either way it is strip_by_grid's.
    if (bucket_strip_.empty()) return strip_by_grid(t);
    const std::size_t buckets = bucket_strip_.size() - 1;
    const std::size_t b = std::min(buckets - 1, static_cast<std::size_t>((t - edges.front()) * bucket_scale_));
    const std::size_t lo = bucket_strip_[b], hi = bucket_strip_[b + 1];
    if (!(edges[lo] <= t && t < edges[hi + 1])) return strip_by_grid(t);
    // A bucket holds at most one edge where the strips are uniform: whether t
    // lies past it, without a branch that t's position would decide at random.
    if (hi - lo <= 1) return lo + static_cast<std::size_t>(lo < hi) * static_cast<std::size_t>(edges[lo + 1] <= t);
    const auto first = edges.begin() + static_cast<std::ptrdiff_t>(lo) + 1;
    const auto last = edges.begin() + static_cast<std::ptrdiff_t>(hi) + 1;
    return static_cast<std::size_t>(std::upper_bound(first, last, t) - edges.begin()) - 1;
}

inline double MarginalCdf::operator()(double t) const {
    if (std::isnan(t)) return t;
    if (!(t > edges.front())) return 0.0;
    if (!(t < edges.back())) return 1.0;
    return interpolate(strip_of(t), t);
}

/// The binning whose cells are the `strips` strips across parameter `axis` of
/// `domain` (axis 1 needs a 2D domain). `line` supplies an unbounded line's
/// half_line_scale and line_center (BinResolution); its cell counts are ignored.
Binning strip_binning(const Domain& domain, int axis, int strips, const BinResolution& line = {});

/// Strips across parameter `axis` of `domain` that follow where a pilot
/// sample's mass lies: the cuts of strips / 4 uniform strips joined with the
/// cuts at strips / 4 quantiles of `values` (the pilot's parameter values
/// along the axis; NaN left out), each of those strips halved into two
/// siblings of equal width (the refinement's error estimate compares
/// siblings). A light of 5e-4 sr spans a few of the uniform strips and lies
/// between their cubature nodes; its quantile strips hold it. With fewer
/// than `strips` finite values, the uniform strips of strip_binning.
Binning pilot_strip_binning(const Domain& domain, int axis, int strips, std::span<const double> values,
                            const BinResolution& line = {});

struct CdfRefinement {
    /// Split sibling strips whose interpolation error estimate (as a CDF
    /// difference) exceeds this; 0 never splits.
    double interpolation_target = 0.0;
    std::size_t max_strips = 0;  ///< no split beyond this many strips in all
    /// Interior cuts across the other parameter (2D domains): every strip is
    /// integrated as the rows between them, ascending.
    std::vector<double> cross_cuts;
};

/// Tabulates the marginal CDF along the strips of `strips` (from strip_binning,
/// an even number), refined as `refinement` asks.
MarginalCdf tabulate_marginal_cdf(const Binning& strips, int axis, const BatchPdf& pdf,
                                  const QuadratureOptions& options, const ParallelFor& parallel_for = serial_for,
                                  const CdfRefinement& refinement = {});

/// The parameter values where `cdf` reaches k / parts, k = 1 .. parts - 1, and
/// towards each end 10^-j of the mass from it, down to 10^-6 (inverse linear
/// interpolation): rows of 1 / parts of the mass each, and outermost rows that
/// hold at most 10^-6, so that mass a row's cubature misses at its edge (a
/// peak's tail) is bounded by the outer rows' or lies in narrow inner rows.
std::vector<double> quantile_cuts(const MarginalCdf& cdf, int parts);

}  // namespace warpcheck::chi2
