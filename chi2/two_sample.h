// Two-sample tests: whether two sets of samples come from one distribution,
// when neither distribution is known. What judges two implementations of one
// warp whose draws are independent (another build, a GPU, another language):
//  - chi-square homogeneity on cells (a 2 x K contingency table), the cells
//    cut adaptively at quantiles of the pooled samples, so that every cell
//    holds about the same number of samples whatever the density;
//  - Anderson-Darling k-sample (Scholz and Stephens 1987) on a marginal, in
//    its form for ties (float samples repeat values).
// Both are invariant to which sample is called first; the cells depend on the
// pooled samples only, so the test's null law is the permutation law of the
// labels given the pool (asymptotically chi-square).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "chi2/pearson.h"

namespace warpcheck::chi2 {

/// The chi-square homogeneity test of two histograms over the same cells.
struct HomogeneityResult {
    double statistic = 0.0;
    int dof = 0;               ///< terms - 1
    double p_value = 0.0;      ///< upper tail of chi^2(dof); NaN with fewer than 2 terms
    std::size_t terms = 0;     ///< cells used, after merging small ones
    std::size_t merged_cells = 0;  ///< cells merged into a neighbour for want of expected counts
    /// n_a n_b / (n_a + n_b): the sample size a one-sample test would need for
    /// the same power against a difference between the two distributions.
    double effective_samples = 0.0;
    /// Per term: (a - E_a) / sqrt(E_a), the standardised deviation of sample a
    /// (sample b's is the same with the opposite sign, scaled by sqrt(n_a / n_b)).
    std::vector<double> residual;
};

/// Pearson's statistic of the 2 x K table: sum over cells of
/// (sqrt(n_b / n_a) a_k - sqrt(n_a / n_b) b_k)^2 / (a_k + b_k). A cell whose
/// expected count in the smaller sample, min(n_a, n_b) (a_k + b_k) / (n_a + n_b),
/// is below `min_expected` is merged with the next (the last with the one
/// before): the chi-square law needs ~5 expected per cell (Cochran 1954).
HomogeneityResult homogeneity_test(std::span<const uint64_t> a, std::span<const uint64_t> b,
                                   double min_expected = kMinExpectedCount);

/// Cells for two samples of points in a plane (u, v), or on a line (v unused):
/// `strips` strips along u at quantiles of the pooled samples' u, each cut into
/// `cells_per_strip` cells at quantiles of the pooled v within it. A cell's
/// edges are values; a value equal to an edge goes to the cell above it, so
/// tied values stay together (a cell may then hold more than its share).
class AdaptiveCells {
public:
    using Point = std::array<double, 2>;
    /// `dims` is 1 (u only) or 2. NaN coordinates are not allowed (callers count
    /// and drop them first).
    AdaptiveCells(std::span<const Point> a, std::span<const Point> b, int dims, int strips, int cells_per_strip);

    std::size_t cell_count() const { return u_edges_.size() * static_cast<std::size_t>(cells_per_strip_); }
    std::size_t cell_of(const Point& p) const;
    /// The counts of `points` per cell.
    std::vector<uint64_t> counts(std::span<const Point> points) const;
    /// The interior edges along u, and per strip the interior edges along v.
    const std::vector<double>& u_edges() const { return u_edges_; }
    const std::vector<std::vector<double>>& v_edges() const { return v_edges_; }

private:
    int dims_;
    int cells_per_strip_;
    std::vector<double> u_edges_;                ///< strips' lower edges (the first is -inf)
    std::vector<std::vector<double>> v_edges_;   ///< per strip, its cells' lower edges (the first is -inf)
};

/// The two-sample Anderson-Darling statistic of Scholz and Stephens (1987),
/// the k-sample statistic for k = 2 in its form for ties (A^2_akN, their
/// equation 7: midranks over the pooled distinct values), with its
/// standardisation and p-value.
struct AndersonDarlingTwoSample {
    double a2 = 0.0;            ///< A^2_akN
    double standardized = 0.0;  ///< (A^2 - (k - 1)) / sigma_N, sigma_N from the paper's variance formula
    /// Upper tail of A^2's limiting law, which for k = 2 is the one-sample
    /// Anderson-Darling law (sum over j of chi^2_1 / (j (j + 1))).
    double p_value = 0.0;
    std::size_t distinct = 0;   ///< distinct values of the pooled samples
};

/// Both samples non-empty, no NaN; at least 4 values together (the variance
/// formula divides by (N - 1)(N - 2)(N - 3)), else NaN figures.
AndersonDarlingTwoSample anderson_darling_two_sample(std::span<const double> a, std::span<const double> b);

}  // namespace warpcheck::chi2
