// A localised statistic next to Pearson's: the cell whose count is least
// likely under the model, with its own multiple-test-corrected p-value.
// Pearson's statistic sums ~1000 squared residuals, so a deviation confined to
// one or a few cells drowns in the other cells' noise (a 20% excess in one cell
// of 1000 adds ~40 to a statistic whose standard deviation is ~45); the largest
// residual sees it at once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "chi2/parallel.h"

namespace warpcheck::chi2 {

/// The share of a chi-square check's level that the largest residual gets
/// (weighted Bonferroni, chi2/min_p.h); Pearson's statistic keeps the rest.
/// Broad deviations are the common warp bug, and at 80% of the level Pearson's
/// critical value moves by ~1% of its noise; a one-cell deviation large enough
/// to matter has a p-value orders of magnitude below the level, so 20% costs
/// the residual little.
inline constexpr double kLocalLevelShare = 0.2;

struct LocalResidual {
    std::size_t cell = 0;         ///< the cell with the smallest per-cell p-value
    double residual = 0.0;        ///< its (observed - expected) / sqrt(expected)
    double cell_p_value = 1.0;    ///< its two-sided exact binomial p-value
    std::size_t cells_tested = 0; ///< cells with a positive expected count
    /// Sidak over the cells tested: 1 - (1 - cell_p_value)^cells_tested. Cell
    /// counts of a multinomial are negatively correlated, for which Sidak's
    /// correction is slightly conservative.
    double p_value = 1.0;
};

/// The largest-residual test of `counts` (n samples in all) against
/// `expected` (n times each cell's probability). Per cell, the count is
/// Binomial(n, expected / n); its two-sided p-value is twice the smaller tail,
/// at most 1 (Boost.Math's binomial distribution).
LocalResidual largest_cell_residual(std::span<const uint64_t> counts, std::span<const double> expected, uint64_t n);

/// The same where each cell's expectation is known only within [lower, upper]
/// (chi2/pearson.h): a count above the band is judged by the upper tail at
/// `upper`, one below it by the lower tail at `lower`, one inside it is not
/// evidence (p 1); each is at least the p-value at the true expectation when
/// it lies in the band, so the test stays conservative. The residual reported
/// is the distance to the band over sqrt(upper). The cells' p-values are
/// computed on `parallel_for`; the result does not depend on it.
LocalResidual largest_cell_residual(std::span<const uint64_t> counts, std::span<const double> expected,
                                    std::span<const double> lower, std::span<const double> upper, uint64_t n,
                                    const ParallelFor& parallel_for = serial_for);

}  // namespace warpcheck::chi2
