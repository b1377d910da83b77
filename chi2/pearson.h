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
    /// The noncentrality the p-value allows for: sum over terms of
    /// band^2 / expected (0 without bands: the central chi-square).
    double noncentrality = 0.0;
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

/// The same test where each expected count is known only to within +-band
/// (its quadrature error, the density's float noise, the float resolution of
/// samples at the cell's edges). If the true expectations are E + d with
/// |d| <= band, Pearson's statistic computed with E follows (asymptotically,
/// as under local alternatives) a noncentral chi^2(dof) with noncentrality
/// sum d^2 / E, at most lambda = sum band^2 / E over the terms (pooled cells'
/// bands add up); its upper tail grows with the noncentrality, so the p-value
/// from noncentral chi^2(dof, lambda) is conservative. A band of a tenth of a
/// cell's Poisson deviation on every one of 1000 cells gives lambda = 10,
/// against the statistic's own deviation of 45: bands well below the noise cost
/// almost no power, where a per-cell worst case would cost each term.
PearsonResult pearson_test(std::span<const double> observed, std::span<const double> expected,
                           std::span<const double> band, double min_expected = kMinExpectedCount);

/// The upper-tail probability of the noncentral chi^2(dof, lambda) at x (the
/// central one when lambda is 0; NaN for invalid input).
double chi_square_upper_tail(double x, double dof, double lambda);

/// The upper-tail probability of chi^2(dof) at x (NaN for invalid input).
double chi_square_upper_tail(double x, double dof);

}  // namespace warpcheck::chi2
