// Evidence of the BSDF checks: maps on the sphere of wi (observed, expected,
// residual per cell), the worst cells, and curves against an angle.
#pragma once

#include <string>

#include "chi2/binning.h"
#include "chi2/chi2_test.h"
#include "reports/result.h"
#include "validate/checks/shared/cell_evidence.h"

namespace warpcheck::bsdf {

/// validate/checks/shared/cell_evidence.h's, with the axes named for wi.
Plot cell_heatmaps(const chi2::Binning& binning, const chi2::Chi2Outcome& o, const std::string& title);

/// validate/checks/shared/cell_evidence.h's, with the axes named for wi.
Table worst_cells(const chi2::Binning& binning, const chi2::Chi2Outcome& o);

}  // namespace warpcheck::bsdf
