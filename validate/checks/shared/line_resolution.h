// How finely the chi-square and unbinned checks cut an unbounded line (a
// half-line in either direction, or the whole real line): where its cells are
// finest and on what length scale, derived from the case's own density and
// samples where the case does not set them.
#pragma once

#include "chi2/domain_parts.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

/// The case's chi2_resolution with, on an unbounded line, the fields the case
/// left 0 filled in:
///   - line_center (real line): the median of the warp's outputs over a fixed
///     grid of inputs (the same for every seed, and none of the test's own
///     samples, so the cells do not depend on the counts they bin);
///   - half_line_scale: 1 / pdf at the finite end, or at the centre: the
///     density's own length scale there (1/rate for an exponential, about
///     2.5 sigma for a normal), so the cells follow the distribution whatever
///     its scale; 1 where that is not a positive finite number.
/// Other domains: the case's chi2_resolution as it is.
chi2::BinResolution line_resolution(const WarpCase& warp);

}  // namespace warpcheck
