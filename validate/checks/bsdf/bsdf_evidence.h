// Evidence of the BSDF checks: maps on the sphere of wi (observed, expected,
// residual per cell), the worst cells, and curves against an angle.
#pragma once

#include <string>

#include "chi2/binning.h"
#include "chi2/chi2_test.h"
#include "reports/result.h"

namespace warpcheck::bsdf {

/// Observed, expected and residual counts per cell of the sphere of wi, as
/// heatmaps over (phi_i, cos theta_i); the residual on a diverging scale at
/// least +-4 wide, so that noise stays pale.
Plot cell_heatmaps(const chi2::Binning& binning, const chi2::Chi2Outcome& o, const std::string& title);

/// The eight cells with the largest |residual| (a sample in a cell of zero
/// expectation first).
Table worst_cells(const chi2::Binning& binning, const chi2::Chi2Outcome& o);

}  // namespace warpcheck::bsdf
