// Cells of about equal probability: the classes of a chi-square test placed at
// the quantiles of the distribution tested (Mann and Wald's equiprobable
// classes), so that every cell holds about N / cells samples wherever the
// mass lies. A lobe of 1e-6 sr gets as many cells as a uniform sphere; a
// uniform grid puts such a lobe, or a narrow Beckmann lobe, into its top row
// and tests only its azimuth.
//
// Where the quantiles come from: a pilot sample, drawn from a stream of its
// own, independent of the samples the test counts. Rows lie at the quantiles
// of the v parameter, and in each row the columns at the quantiles of u among
// the row's pilot points (1D domains: columns at the quantiles of u). The
// cells are fixed before the tested samples are drawn, so the test stays
// exact under the null hypothesis whatever the pilot looked like; expected
// counts still come from the density integrated over each cell
// (chi2/quadrature.h). A pilot finds a support that quadrature nodes step
// over (a 1e-6 sr lobe lies between the nodes of any fixed rule on the
// sphere), which the density's own CDFs, tabulated by cubature, would not.
//
// Float resolution: a cell narrower than the samples' float resolution tests
// rounding, not the warp. As for uniform cells (float_aware_resolution), every
// row must span at least 3 sqrt(E) float steps of v where it lies, E being its
// cells' expected count (the band of kEdgeFloatSteps steps at each edge then
// stays within a third of a Poisson deviation); narrower rows are merged with
// the next, and the columns of every row are halved in number until each
// spans as many float steps of u. Spherical caps read z off x and y near the
// poles (SphericalCap::polar_height), so their rows can be as fine near the
// pole as the samples' x and y are.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "chi2/binning.h"
#include "chi2/chi2_test.h"

namespace warpcheck::chi2 {

/// Pilot points per cell: the pilot's quantiles then place each edge within
/// about 1 / sqrt(64) = 12% of a cell's probability (the cells' probabilities
/// vary that much; the test's expected counts are integrated, not assumed).
inline constexpr std::size_t kPilotPointsPerCell = 64;

struct EqualProbabilityCells {
    CellEdges edges;            ///< empty when the pilot had too few usable points
    std::size_t pilot_used = 0;       ///< pilot points inside the domain with finite parameters
    std::size_t rows_merged = 0;      ///< quantile rows merged into a neighbour for float resolution (or ties)
    int column_halvings = 0;          ///< times the columns were halved for float resolution
};

/// Below this share of its cells in effective use, a uniform grid gives way
/// to cells of equal probability: the effective number of cells is
/// 1 / sum p_i^2 over the pilot's shares p_i (all of them for an even spread,
/// one for a lobe inside one cell). A grid that uses a quarter of its 1024
/// cells still resolves each marginal in 16 or more effectively occupied rows
/// and columns, and the row states the power its cells give (a marginal they
/// do not resolve makes it "weak"); and its edges stay where a table's
/// pixels end (8 x 8 pixels on 32 x 32 cells: no jump inside any cell, which
/// cells at quantiles would cut through, where the cubature's error estimate
/// is least reliable).
inline constexpr double kMinEffectiveCellShare = 0.25;

/// The pilot's effective number of cells of `grid` (1 / sum p_i^2), or 0
/// when no pilot point lies in the domain.
double effective_cells(const Binning& grid, std::span<const SamplePoint> pilot);

/// The cells of `grid` (its domain, cell counts and line parameters; a
/// uniform grid) moved to the quantiles of `pilot`, for a test of `samples`
/// samples. Empty edges (keep `grid`) when fewer than 2 pilot points per cell
/// are usable.
EqualProbabilityCells equal_probability_cells(const Binning& grid, std::span<const SamplePoint> pilot,
                                              uint64_t samples);

}  // namespace warpcheck::chi2
