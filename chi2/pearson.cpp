#include "chi2/pearson.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <boost/math/distributions/chi_squared.hpp>

namespace warpcheck::chi2 {

double chi_square_upper_tail(double x, double dof) {
    if (!(dof > 0.0) || !std::isfinite(dof) || std::isnan(x)) return std::numeric_limits<double>::quiet_NaN();
    if (x <= 0.0) return 1.0;
    if (std::isinf(x)) return 0.0;
    const boost::math::chi_squared_distribution<double> dist(dof);
    return boost::math::cdf(boost::math::complement(dist, x));
}

PearsonResult pearson_test(std::span<const double> observed, std::span<const double> expected, double min_expected) {
    if (observed.size() != expected.size()) throw std::invalid_argument("pearson_test: size mismatch");
    const std::size_t n = observed.size();
    constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
    PearsonResult res;
    res.term_of_cell.assign(n, kNone);

    // Regular cells keep their own term.
    std::vector<double> term_obs, term_exp;
    std::vector<std::size_t> small;
    for (std::size_t i = 0; i < n; ++i) {
        if (expected[i] >= min_expected) {
            res.term_of_cell[i] = term_obs.size();
            term_obs.push_back(observed[i]);
            term_exp.push_back(expected[i]);
        } else {
            small.push_back(i);  // includes NaN expectations: they poison a pool, visibly
        }
    }
    const std::size_t regular = term_obs.size();
    res.small_cells = small.size();
    std::stable_sort(small.begin(), small.end(), [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });

    // Gather small cells into pools of at least min_expected.
    double pool_obs = 0.0, pool_exp = 0.0;
    std::vector<std::size_t> open;  // cells of the pool being filled
    for (std::size_t i : small) {
        pool_obs += observed[i];
        pool_exp += expected[i];
        open.push_back(i);
        if (pool_exp >= min_expected) {
            for (std::size_t c : open) res.term_of_cell[c] = term_obs.size();
            term_obs.push_back(pool_obs);
            term_exp.push_back(pool_exp);
            pool_obs = pool_exp = 0.0;
            open.clear();
            ++res.pools;
        }
    }
    if (!open.empty()) {
        // The leftover pool is merged, never dropped.
        std::size_t target = kNone;
        if (res.pools > 0) {
            target = term_obs.size() - 1;
        } else if (regular > 0) {
            target = 0;
            for (std::size_t t = 1; t < regular; ++t)
                if (term_exp[t] < term_exp[target]) target = t;
        }
        if (target == kNone) {  // nothing else: the leftover is the only term
            target = term_obs.size();
            term_obs.push_back(0.0);
            term_exp.push_back(0.0);
            ++res.pools;
        }
        term_obs[target] += pool_obs;
        term_exp[target] += pool_exp;
        for (std::size_t c : open) res.term_of_cell[c] = target;
    }

    res.terms = term_obs.size();
    res.dof = static_cast<int>(res.terms) - 1;
    if (res.dof < 1) {
        res.statistic = res.p_value = std::numeric_limits<double>::quiet_NaN();
        return res;
    }
    double stat = 0.0;
    for (std::size_t t = 0; t < res.terms; ++t) {
        const double d = term_obs[t] - term_exp[t];
        stat += d * d / term_exp[t];
    }
    res.statistic = stat;
    res.p_value = chi_square_upper_tail(stat, res.dof);
    return res;
}

}  // namespace warpcheck::chi2
