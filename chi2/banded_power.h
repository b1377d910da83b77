// Stated power of the banded tests (chi2::banded_statistics): the smallest
// tilt of a marginal that such a test detects with a given probability, when
// every sample's transform is known only within a band.
//
// The model, in the asymptotic scale of chi2/power.h: sqrt(n) (F_n - F) is a
// Brownian bridge B plus the tilt's drift delta u (1 - u). A band that moves
// the ends of every sample's interval by at most `shift` from its ideal
// transform moves the envelope of chi2::banded_statistics by at most c =
// sqrt(n) shift from the ideal empirical CDF, up and down (moving it along
// the probability axis by `shift` changes the bridge by O(sqrt(shift)) of its
// own scale only, which is ignored). So the banded statistics are those of
// the distance from y = B + drift to the band [-c, c]: D+ = max(0, sup y - c),
// D- = max(0, sup(-y) - c), A^2 = integral of max(0, |y| - c)^2 / (u (1 - u)).
// Their power is simulated on 1000 bridges of a 512-point grid, as in
// chi2/power.cpp (the same continuity correction of the extremes), from a
// fixed stream of this file's own: the figure is the same on every run.
#pragma once

#include <cstdint>

#include "chi2/unbinned.h"

namespace warpcheck::chi2 {

/// The smallest tilt eps that the banded `test`, whose interval ends lie
/// within `shift` of the ideal transforms, detects with probability `power`
/// at `level` with n samples. NaN when no drift up to sqrt(n) eps = 512
/// reaches the power (a band too wide for any stated power). With shift 0 it
/// is unbinned_tilt_for_power's figure, to the simulations' noise.
double banded_tilt_for_power(UnbinnedTest test, double level, double shift, uint64_t n, double power = 0.9);

/// Simulates the bridges now, which the first banded_tilt_for_power of a
/// process does otherwise: a process that forks workers calls it first, and
/// every worker shares them (a few tens of milliseconds each would redo).
void prepare_banded_power();

}  // namespace warpcheck::chi2
