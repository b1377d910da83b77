// Pearson's chi-square statistic with pooling of small cells, and its p-value.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace warpcheck::chi2 {

/// Cells expected to hold fewer samples than this are pooled: below ~5 the
/// chi-square approximation to Pearson's statistic breaks down (Cochran 1954).
inline constexpr double kMinExpectedCount = 5.0;

struct PearsonResult {
    double statistic = 0.0;
    int dof = 0;                 ///< terms - 1 (the counts' total is fixed)
    double p_value = 0.0;        ///< upper tail; NaN when it cannot be computed
    std::size_t terms = 0;       ///< cells actually used: regular cells plus pools
    std::size_t small_cells = 0; ///< cells below the minimum, merged into pools
    std::size_t pools = 0;       ///< pooled terms formed from them
    /// Per input cell, the term it went into (terms are numbered regular cells
    /// first, in cell order, then pools).
    std::vector<std::size_t> term_of_cell;
};

/// Pools the cells whose expected count is below `min_expected`, then computes
/// Pearson's statistic sum (O - E)^2 / E over the terms, dof = terms - 1, and
/// the p-value P(X >= statistic) for X ~ chi^2(dof), from Boost.Math's
/// chi_squared distribution through the complement of the cdf (1 - cdf loses
/// every digit of small p-values).
///
/// Pooling: the small cells, taken in increasing order of expected count (ties
/// by cell index), are gathered into pools, each closed once it reaches
/// `min_expected`. A leftover pool that stays below the minimum is merged into
/// the last closed pool, or, when there is none, into the regular cell with the
/// smallest expected count. No cell is ever dropped: every observation counts.
/// Fewer than two terms leave no degrees of freedom: statistic and p-value are NaN.
PearsonResult pearson_test(std::span<const double> observed, std::span<const double> expected,
                           double min_expected = kMinExpectedCount);

/// The upper-tail probability of chi^2(dof) at x (NaN for invalid input).
double chi_square_upper_tail(double x, double dof);

}  // namespace warpcheck::chi2
