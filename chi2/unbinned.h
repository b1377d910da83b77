// Unbinned goodness-of-fit tests of a continuous distribution: Kolmogorov-
// Smirnov, Kuiper and Anderson-Darling, on the probability-integral transforms
// u_i = F(x_i) of the samples (uniform on [0, 1] when the model F is right).
// Binning throws away where in a cell a sample fell and spreads a broad
// deviation over many cells' noise; these statistics see the whole empirical
// CDF at once, so a smooth tilt is found with about half the deviation that
// Pearson's statistic needs at 10^6 samples.
//
// p-values: Boost.Math 1.74 has no Kolmogorov distribution, so all three come
// from published asymptotic distributions with published finite-n corrections
// (sources next to each formula in unbinned.cpp).
#pragma once

#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

namespace warpcheck::chi2 {

enum class UnbinnedTest {
    KolmogorovSmirnov,  ///< sup |F_n - F|: most sensitive near the median
    Kuiper,             ///< sup (F_n - F) + sup (F - F_n): invariant to where a circle starts
    AndersonDarling,    ///< integral of (F_n - F)^2 / (F (1 - F)) dF: weights the tails
};

inline constexpr UnbinnedTest kUnbinnedTests[] = {UnbinnedTest::KolmogorovSmirnov, UnbinnedTest::Kuiper,
                                                  UnbinnedTest::AndersonDarling};

/// "ks", "kuiper", "ad": the short name used in figure names.
std::string_view short_name(UnbinnedTest test);

struct UnbinnedStatistics {
    std::size_t n = 0;
    double d_plus = 0.0;   ///< max_i (i/n - u_(i))
    double d_minus = 0.0;  ///< max_i (u_(i) - (i-1)/n)
    double ad = 0.0;       ///< Anderson-Darling A^2

    double ks() const { return d_plus > d_minus ? d_plus : d_minus; }
    double kuiper() const { return d_plus + d_minus; }
    double statistic(UnbinnedTest test) const;
    /// The upper-tail p-value of `test` at this sample size.
    double p_value(UnbinnedTest test) const;
};

/// Sorts values of [0, 1] ascending, in O(n) for values spread over [0, 1]
/// (radix passes on floor(u 2^20), then a sort of each run of equal keys).
/// NaN values are not allowed (callers drop them first).
void sort_unit_values(std::vector<double>& values);

/// The three statistics of sorted transforms u_(1) <= ... <= u_(n) in [0, 1].
/// Values are clamped to [1e-300, 1 - 2^-53] inside A^2's logarithms, so a
/// sample exactly at an end of the support costs (1/n) * 690 at most instead of
/// an infinity.
UnbinnedStatistics unbinned_statistics(std::span<const double> sorted_u);

/// Lower bounds of the three statistics of n ideal transforms U_i that are
/// known only to lie in intervals: U_i in [lo_i, hi_i] (0 <= lo_i <= hi_i <= 1),
/// given as the n lower ends sorted ascending and the n upper ends sorted
/// ascending (each on its own: which lower end goes with which upper end does
/// not matter). The empirical CDF E_n(t) of the U_i then lies between
/// #{hi_i <= t} / n and #{lo_i <= t} / n at every t, and each statistic is
/// bounded below by its value for the function within that envelope closest
/// to t: D+ >= max_k (k/n - hi_(k)), D- >= max_k (lo_(k) - (k-1)/n), and A^2 >=
/// n times the integral of dist(t, envelope)^2 / (t (1 - t)), which is exact
/// piece by piece. If the U_i are iid uniform (the ideal, continuous samples of
/// the model), the p-values of these bounds (UnbinnedStatistics::p_value) are
/// conservative: each bound is at most the statistic it bounds. With lo = hi
/// (no band) they are the ordinary statistics of unbinned_statistics (to
/// rounding in A^2).
UnbinnedStatistics banded_statistics(std::span<const double> sorted_lo, std::span<const double> sorted_hi);

/// Asymptotic Kolmogorov upper tail Q_K(lambda) = P(sup |B| > lambda) of the
/// Brownian bridge B.
double kolmogorov_q(double lambda);
/// Asymptotic Kuiper upper tail Q_V(lambda) = P(sup B - inf B > lambda).
double kuiper_q(double lambda);
/// Asymptotic Anderson-Darling CDF P(A^2 <= z) (n = infinity).
double anderson_darling_asymptotic_cdf(double z);
/// P(A^2 <= z) for n samples: the asymptotic CDF plus Marsaglia and
/// Marsaglia's finite-n correction.
double anderson_darling_cdf(std::size_t n, double z);

/// The statistic's value (in its own asymptotic scale: sqrt(n)-scaled D for
/// KS, sqrt(n)-scaled V for Kuiper, A^2 for AD) above which the asymptotic
/// upper tail is `level`.
double asymptotic_critical_value(UnbinnedTest test, double level);

}  // namespace warpcheck::chi2
