// Evidence of the chi-square checks (chi2, bsdf_chi2): the observed, expected
// and residual counts per cell as heatmaps, and the cells that deviate most.
// One builder for both, so that a change of cells (equal probability) shows
// the same way in each.
#pragma once

#include <string>
#include <vector>

#include "chi2/binning.h"
#include "chi2/chi2_test.h"
#include "reports/result.h"

namespace warpcheck {

/// Axis names for the evidence: the binning's parameter labels unless given
/// (a BSDF's "phi_i", "cos theta_i").
struct CellAxes {
    std::string u, v;
};

/// Observed, expected and residual counts per cell as heatmaps over the
/// parameter rectangle; cells of equal probability (Binning::has_own_edges)
/// as the grid they are, rows by v's quantiles and columns by u's in each
/// row. The residual on a diverging scale at least +-4 wide, so that noise
/// stays pale and a real deviation stands out.
Plot cell_heatmaps(const chi2::Binning& binning, const chi2::Chi2Outcome& o, const std::string& title,
                   const CellAxes& axes = {});

/// The eight cells with the largest |residual| (a sample in a cell of zero
/// expectation first; ties to the lower cell).
Table worst_cells(const chi2::Binning& binning, const chi2::Chi2Outcome& o, const CellAxes& axes = {});

/// What chi2::refine_by_pilot did to a check's cubature, as the figures
/// pilot_partitioned_cells, pilot_corrected_cells and pilot_corrected_mass
/// (chi2, bsdf_chi2, bsdf_albedo).
void add_pilot_refinement_figures(std::vector<Figure>& figures, const chi2::PilotRefinement& p);

}  // namespace warpcheck
