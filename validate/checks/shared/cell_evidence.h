// Evidence of the chi-square checks (chi2, bsdf_chi2): the observed, expected
// and residual counts per cell as heatmaps, and the cells that deviate most.
// One builder for both, so that a change of cells (equal probability) shows
// the same way in each.
#pragma once

#include <cstddef>
#include <optional>
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

/// The cell a chi-square row's evidence rings as its largest residual, and
/// that residual: the check's (figures local_cell and local_max_residual: the
/// cell of the smallest per-cell p-value). Where that p-value underflowed to 0
/// (local_p_value 0), every cell at 0 ties and the check's is only the first
/// of them: the ring then goes to the cell of the largest |residual| of the
/// row's plotted residuals, the departure the table of cells lists first.
struct RingedCell {
    std::size_t index = 0;  ///< the cell: a residual heatmap's value index, or the residual series' point
    double residual = 0.0;
};
std::optional<RingedCell> ringed_cell(const CheckResult& r);

/// The |residual| at which one cell alone fails at the row's level (r.level),
/// its largest residual being judged at chi2::kLocalLevelShare of it: in the
/// normal approximation of a cell's binomial count, two-sided p = erfc(z /
/// sqrt 2) at the cell level 1 - (1 - share level)^(1 / cells tested). For the
/// marks only; the check judges the exact binomial p-value. None before the
/// level is settled.
std::optional<double> single_cell_limit(const CheckResult& r);

/// The marks of a chi-square row's plots (JudgedRules::marks): on each
/// residual heatmap the ringed cell and single_cell_limit on its colour scale;
/// on a residual point plot the limit's two lines and the ringed point; under
/// each heatmap or point plot `rule` (what fails the row), followed by the
/// single cell's limit.
void mark_residual_plots(CheckResult& r, const std::string& rule);

/// What chi2::refine_by_pilot did to a check's cubature, as the figures
/// pilot_partitioned_cells, pilot_corrected_cells, pilot_corrected_mass and pilot_sharpened_cells
/// (chi2, bsdf_chi2, bsdf_albedo).
void add_pilot_refinement_figures(std::vector<Figure>& figures, const chi2::PilotRefinement& p);

}  // namespace warpcheck
