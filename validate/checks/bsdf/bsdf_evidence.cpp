#include "validate/checks/bsdf/bsdf_evidence.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace warpcheck::bsdf {
namespace {

const CellAxes kWiAxes{"phi_i", "cos theta_i"};

}  // namespace


Plot cell_heatmaps(const chi2::Binning& b, const chi2::Chi2Outcome& o, const std::string& title) {
    return warpcheck::cell_heatmaps(b, o, title, kWiAxes);
}

Table worst_cells(const chi2::Binning& b, const chi2::Chi2Outcome& o) { return warpcheck::worst_cells(b, o, kWiAxes); }

}  // namespace warpcheck::bsdf
