#include "chi2/pearson.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/non_central_chi_squared.hpp>

namespace warpcheck::chi2 {

double chi_square_upper_tail(double x, double dof) {
    if (!(dof > 0.0) || !std::isfinite(dof) || std::isnan(x)) return std::numeric_limits<double>::quiet_NaN();
    if (x <= 0.0) return 1.0;
    if (std::isinf(x)) return 0.0;
    const boost::math::chi_squared_distribution<double> dist(dof);
    return boost::math::cdf(boost::math::complement(dist, x));
}

double chi_square_upper_tail(double x, double dof, double lambda) {
    if (lambda == 0.0) return chi_square_upper_tail(x, dof);
    if (!(dof > 0.0) || !std::isfinite(dof) || std::isnan(x) || !(lambda > 0.0) || !std::isfinite(lambda))
        return std::numeric_limits<double>::quiet_NaN();
    if (x <= 0.0) return 1.0;
    if (std::isinf(x)) return 0.0;
    const boost::math::non_central_chi_squared_distribution<double> dist(dof, lambda);
    return boost::math::cdf(boost::math::complement(dist, x));
}

PearsonResult pearson_test(std::span<const double> observed, std::span<const double> expected, double min_expected) {
    return pearson_test(observed, expected, {}, min_expected);
}

namespace {

/// Pearson's terms: per term its observed and expected counts and its band.
struct Terms {
    std::vector<double> obs, exp, band;
    void push(double o, double e, double b) {
        obs.push_back(o);
        exp.push_back(e);
        band.push_back(b);
    }
    std::size_t size() const { return obs.size(); }
};

/// Merges the leftover pool (below the minimum) into the last closed pool, or
/// into the regular term with the smallest expectation, or makes it the only
/// term: never dropped.
std::size_t leftover_target(Terms& t, std::size_t regular, PearsonResult& res) {
    if (res.pools > 0) return t.size() - 1;
    if (regular > 0) {
        std::size_t target = 0;
        for (std::size_t k = 1; k < regular; ++k)
            if (t.exp[k] < t.exp[target]) target = k;
        return target;
    }
    t.push(0.0, 0.0, 0.0);
    ++res.pools;
    return t.size() - 1;
}

/// Gathers the small cells (in increasing order of expectation) into pools of
/// at least min_expected, appended to `t` (see pearson.h).
void pool_small_cells(std::vector<std::size_t> small, std::span<const double> observed,
                      std::span<const double> expected, std::span<const double> band, double min_expected,
                      std::size_t regular, Terms& t, PearsonResult& res) {
    const auto band_of = [&](std::size_t i) { return band.empty() ? 0.0 : band[i]; };
    std::stable_sort(small.begin(), small.end(), [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });
    double pool_obs = 0.0, pool_exp = 0.0, pool_band = 0.0;
    std::vector<std::size_t> open;  // cells of the pool being filled
    for (std::size_t i : small) {
        pool_obs += observed[i];
        pool_exp += expected[i];
        pool_band += band_of(i);
        open.push_back(i);
        if (pool_exp >= min_expected) {
            for (std::size_t c : open) res.term_of_cell[c] = t.size();
            t.push(pool_obs, pool_exp, pool_band);
            pool_obs = pool_exp = pool_band = 0.0;
            open.clear();
            ++res.pools;
        }
    }
    if (open.empty()) return;
    const std::size_t target = leftover_target(t, regular, res);
    t.obs[target] += pool_obs;
    t.exp[target] += pool_exp;
    t.band[target] += pool_band;
    for (std::size_t c : open) res.term_of_cell[c] = target;
}

}  // namespace

PearsonResult pearson_test(std::span<const double> observed, std::span<const double> expected,
                           std::span<const double> band, double min_expected) {
    if (observed.size() != expected.size() || (!band.empty() && band.size() != expected.size()))
        throw std::invalid_argument("pearson_test: size mismatch");
    const std::size_t n = observed.size();
    PearsonResult res;
    res.term_of_cell.assign(n, std::numeric_limits<std::size_t>::max());

    // Regular cells keep their own term.
    Terms t;
    std::vector<std::size_t> small;
    for (std::size_t i = 0; i < n; ++i) {
        if (expected[i] >= min_expected) {
            res.term_of_cell[i] = t.size();
            t.push(observed[i], expected[i], band.empty() ? 0.0 : band[i]);
        } else {
            small.push_back(i);  // includes NaN expectations: they poison a pool, visibly
        }
    }
    res.small_cells = small.size();
    pool_small_cells(std::move(small), observed, expected, band, min_expected, t.size(), t, res);

    res.terms = t.size();
    res.dof = static_cast<int>(res.terms) - 1;
    if (res.dof < 1) {
        res.statistic = res.p_value = std::numeric_limits<double>::quiet_NaN();
        return res;
    }
    double stat = 0.0, lambda = 0.0;
    for (std::size_t k = 0; k < res.terms; ++k) {
        const double d = t.obs[k] - t.exp[k];
        stat += d * d / t.exp[k];
        lambda += t.band[k] * t.band[k] / t.exp[k];
    }
    res.statistic = stat;
    res.noncentrality = lambda;
    res.p_value = chi_square_upper_tail(stat, res.dof, lambda);
    return res;
}

}  // namespace warpcheck::chi2
