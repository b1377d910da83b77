#include "chi2/local_residual.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <boost/math/distributions/binomial.hpp>

namespace warpcheck::chi2 {

namespace {

double two_sided_binomial_p(uint64_t observed, double expected, uint64_t n) {
    const double p = std::clamp(expected / static_cast<double>(n), 0.0, 1.0);
    if (p >= 1.0) return 1.0;
    const boost::math::binomial_distribution<double> law(static_cast<double>(n), p);
    const double k = static_cast<double>(observed);
    const double mean = static_cast<double>(n) * p;
    // The median m of a binomial is floor(np) or ceil(np): for k >= np + 1,
    // P(X >= k) <= 1/2 <= P(X <= k), and the other way round for k <= np - 1,
    // so only the smaller tail is computed there (the same minimum, at half
    // the cost: these are most of the run's incomplete beta calls).
    const auto lower = [&] { return boost::math::cdf(law, k); };
    const auto upper = [&] { return observed == 0 ? 1.0 : boost::math::cdf(boost::math::complement(law, k - 1.0)); };
    const double tail = k >= mean + 1.0 ? upper() : k <= mean - 1.0 ? lower() : std::min(lower(), upper());
    return std::min(1.0, 2.0 * tail);
}

}  // namespace

LocalResidual largest_cell_residual(std::span<const uint64_t> counts, std::span<const double> expected, uint64_t n) {
    return largest_cell_residual(counts, expected, expected, expected, n);
}

LocalResidual largest_cell_residual(std::span<const uint64_t> counts, std::span<const double> expected,
                                    std::span<const double> lower, std::span<const double> upper, uint64_t n,
                                    const ParallelFor& parallel_for) {
    LocalResidual out;
    if (n == 0) return out;
    const std::size_t cells = std::min({counts.size(), expected.size(), lower.size(), upper.size()});
    // The end of the band nearest to the count (the count itself inside it).
    const auto nearest_of = [&](std::size_t c) {
        const double o = static_cast<double>(counts[c]);
        return o < lower[c] ? lower[c] : o > upper[c] ? upper[c] : o;
    };
    // The exact binomial tails (an incomplete beta each, in long double) per
    // block of cells on the executor; the smallest is picked in cell order.
    constexpr std::size_t kBlock = 64;
    std::vector<double> cell_p(cells, 1.0);
    parallel_for((cells + kBlock - 1) / kBlock, [&](std::size_t b) {
        for (std::size_t c = b * kBlock; c < std::min(cells, (b + 1) * kBlock); ++c) {
            if (!(expected[c] > 0.0)) continue;
            const double nearest = nearest_of(c);
            const bool inside = nearest == static_cast<double>(counts[c]) && lower[c] != upper[c];
            cell_p[c] = inside ? 1.0 : two_sided_binomial_p(counts[c], nearest, n);
        }
    });
    for (std::size_t c = 0; c < cells; ++c) {
        if (!(expected[c] > 0.0)) continue;
        ++out.cells_tested;
        const double o = static_cast<double>(counts[c]);
        const double nearest = nearest_of(c);
        const double p = cell_p[c];
        if (out.cells_tested == 1 || p < out.cell_p_value) {
            out.cell = c;
            out.cell_p_value = p;
            out.residual = (o - nearest) / std::sqrt(upper[c]);
        }
    }
    const double m = static_cast<double>(out.cells_tested);
    out.p_value = out.cells_tested == 0 ? 1.0 : -std::expm1(m * std::log1p(-out.cell_p_value));
    return out;
}

}  // namespace warpcheck::chi2
