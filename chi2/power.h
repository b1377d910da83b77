// Stated power: the smallest deviation of a stated family that a test detects
// with 90% probability at a given level, so that a passing result says how
// large a deviation it could have missed.
//
// The family: a linear tilt of a marginal on its probability scale. If U = F(X)
// is uniform under the model, the tilted law has density 1 + eps (2U - 1) on
// [0, 1] (CDF u - eps u (1 - u)): the first-order shape of a density whose
// claimed normalisation is right but whose slope is wrong along that marginal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "chi2/binning.h"
#include "chi2/unbinned.h"

namespace warpcheck::chi2 {

/// The noncentrality lambda at which Pearson's statistic with `dof` degrees of
/// freedom exceeds its level-`level` critical value with probability `power`
/// (the noncentral chi-square law; Boost.Math's find_non_centrality). With
/// `band_noncentrality` > 0 the critical value is the banded test's (the
/// level-`level` quantile of the noncentral chi-square with that
/// noncentrality, as chi2/pearson.h judges): the power of the test as it runs,
/// against a deviation whose own noncentrality is lambda.
double pearson_noncentrality_for_power(double dof, double level, double power = 0.9, double band_noncentrality = 0.0);

/// Per cell, how a tilt of one marginal moves its probability, per unit of
/// eps: the tilted law has density 1 + eps (2 F - 1) along the marginal's CDF
/// F, so a cell gains eps times the integral of (2 F - 1) over it. Computed
/// from the cells as binned: F along v from the rows' cumulative
/// probabilities (1D domains: along u from the columns'), F along u from the
/// cells' mass spread evenly over each one's u range; a cell's F is taken
/// as even over its range (within its row, F along v is; along u, rows are
/// assumed not to shift a cell's share of its column range). `axis`: 0 for u,
/// 1 for v. Probabilities are normalised by their sum.
std::vector<double> tilt_gradient(const Binning& binning, std::span<const double> probability, int axis);

/// The noncentrality that a tilt eps = 1 gives Pearson's statistic over
/// `samples` samples on the terms that pooling made (`term_of_cell`, as
/// PearsonResult has it): n sum over terms (sum of gradient)^2 / (sum of
/// probability). A marginal the cells do not resolve (a lobe in one row)
/// gives almost none: its tilt cannot be seen.
double tilt_noncentrality(std::span<const double> gradient, std::span<const double> probability,
                          std::span<const std::size_t> term_of_cell, uint64_t samples);

/// The first-order change of Pearson's mean per unit tilt, on the same terms:
/// sum over terms (sum of gradient) / (sum of probability). Under a deviation
/// delta the statistic's mean is dof + lambda + sum delta/p (a term whose
/// expected count grows also grows its variance); it is zero on cells of equal
/// probability and large where a lobe's mass sits in a few heavy cells and the
/// tilt takes it from many light ones.
double tilt_mean_shift(std::span<const double> gradient, std::span<const double> probability,
                       std::span<const std::size_t> term_of_cell);

/// The smallest |eps| at which a tilt of either sign moves Pearson's mean by
/// `lambda` beyond its dof: the positive root of per_unit eps^2 - |shift| eps =
/// lambda (per_unit from tilt_noncentrality, shift from tilt_mean_shift), so
/// that the stated power holds for the sign that lowers the mean.
double tilt_for_noncentrality(double lambda, double per_unit, double shift);

/// The tilt eps of one marginal that gives Pearson's statistic the
/// noncentrality `lambda` with n samples: lambda = n eps^2 Var(2U - 1) = n eps^2 / 3.
/// Cells much narrower than the marginal's scale lose a fraction ~1/cells^2
/// of that (below 0.1% at 32 cells per axis), which is ignored.
double pearson_tilt_for_noncentrality(double lambda, uint64_t n);

/// The smallest tilt eps that `test` detects with probability `power` at
/// `level` with n samples. Under the tilt, sqrt(n) (F_n - F) tends to the
/// Brownian bridge plus the drift -sqrt(n) eps u (1 - u); the power at a drift
/// is measured on 1000 simulated bridges on a 512-point grid (a fixed stream,
/// so the figure is the same on every run), and the drift bisected for the
/// target power (1000 bridges: the power is known to +-0.01, the drift to
/// about +-1.5%). The grid's sup falls short of the true sup by ~0.58/sqrt(512);
/// the extremes are corrected by that (uncorrected, the Kuiper figure was
/// detected 96 times in 100 instead of 90: warpcheck_fpr --power-check). Results are cached
/// per (test, level, power): a run evaluates each once.
double unbinned_tilt_for_power(UnbinnedTest test, double level, uint64_t n, double power = 0.9);

}  // namespace warpcheck::chi2
