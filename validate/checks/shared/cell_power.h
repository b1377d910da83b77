// The stated power of a chi-square test as it ran (the chi2 and bsdf_chi2
// checks), and the rule that a row which cannot see a 5% tilt says so.
//
// Power here is the probability that the test, with its cells, its pooling
// and its banded critical value (the noncentrality its expected counts'
// bands allow, chi2/pearson.h), detects a linear tilt 1 + eps (2F - 1) of a
// marginal (chi2/power.h) at the planned level (power_level.h). The tilt that
// each marginal needs for 90% power is computed from the cells' integrals:
// a marginal the cells do not resolve (a lobe inside one row) needs a tilt
// beyond any bound, and the row says it cannot see it. trust/power_simulation.h
// checks the figures by simulating the tilt.
#pragma once

#include <cstdint>
#include <string>

#include "chi2/binning.h"
#include "chi2/chi2_test.h"
#include "validate/checks/check.h"

namespace warpcheck {

/// The effect every statistical row must be able to see: a 5% linear tilt of
/// a marginal on its probability scale (density 0.95 to 1.05 across it), the
/// size of a sharp lobe's width 2% off (its radial marginal moves by about
/// that much) or of a missing Jacobian over part of a domain. A pass whose
/// stated power does not reach it is "weak" (CheckResult::weak).
inline constexpr double kWeakTilt = 0.05;

/// Adds the figures of the stated power of `o`, a chi-square test of
/// `samples` samples on `binning`'s cells at the per-test level `level`:
/// power_noncentrality (the noncentrality detected 90% of the time),
/// power_tilt_eps_<marginal> per parameter of the binning, power_tilt_eps
/// (the weakest marginal's: what the row states) and power_level.
void add_cell_power(CheckResult& r, const chi2::Binning& binning, const chi2::Chi2Outcome& o, double level,
                    uint64_t samples);

/// What a row with stated power figures (add_cell_power's, or any check's
/// power_tilt_eps) could not see, or empty: the weakest marginal when its
/// tilt at 90% power is above kWeakTilt (or not finite).
std::string weakness(const CheckResult& r);

/// "cos theta" -> "cos_theta": a label as part of a figure's name.
std::string figure_label(const std::string& label);

}  // namespace warpcheck
