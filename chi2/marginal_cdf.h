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
// the h^2 law of linear interpolation. Both are set far
// below the 1/sqrt(N) resolution of the unbinned tests (see unbinned_check).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "chi2/binning.h"
#include "chi2/domain.h"
#include "chi2/parallel.h"
#include "chi2/quadrature.h"

namespace warpcheck::chi2 {

struct MarginalCdf {
    int axis = 0;                    ///< 0: the binning's u parameter, 1: its v parameter
    std::vector<double> edges;       ///< strip edges in the parameter, ascending
    std::vector<double> cdf;         ///< the normalised CDF at the edges: 0 ... 1
    double total = 0.0;              ///< the density's integral over the domain (before normalising)
    double quadrature_error = 0.0;   ///< sum of the strips' error estimates, relative to total
    double interpolation_error = 0.0;  ///< estimated max error of the linear interpolation
    std::size_t unconverged_strips = 0;
    uint64_t evaluations = 0;
    uint64_t bad_values = 0;         ///< negative or non-finite density values met

    /// Bound on |tabulated CDF - true CDF| anywhere: both sources added.
    double error_bound() const { return quadrature_error + interpolation_error; }
    /// The CDF at parameter t (0 below the first edge, 1 above the last).
    double operator()(double t) const;
};

/// The binning whose cells are the `strips` strips across parameter `axis` of
/// `domain` (axis 1 needs a 2D domain). `line` supplies an unbounded line's
/// half_line_scale and line_center (BinResolution); its cell counts are ignored.
Binning strip_binning(const Domain& domain, int axis, int strips, const BinResolution& line = {});

/// Tabulates the marginal CDF along the strips of `strips` (from strip_binning).
MarginalCdf tabulate_marginal_cdf(const Binning& strips, int axis, const BatchPdf& pdf,
                                  const QuadratureOptions& options, const ParallelFor& parallel_for = serial_for);

}  // namespace warpcheck::chi2
