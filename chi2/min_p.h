// Combining several tests of one check into one p-value: the smallest p-value,
// Sidak-corrected over the number of tests, 1 - (1 - p_min)^k. Exact for
// independent tests and conservative for positively correlated ones (tests
// of the same samples), so a check that reports it counts as one test in the
// run's family. A NaN among the p-values gives NaN (and NaN fails).
#pragma once

#include <cmath>
#include <initializer_list>
#include <span>

namespace warpcheck::chi2 {

inline double sidak_min_p(std::span<const double> p_values) {
    if (p_values.empty()) return std::nan("");
    double p_min = 1.0;
    for (double p : p_values) {
        if (std::isnan(p)) return p;
        p_min = p < p_min ? p : p_min;
    }
    return -std::expm1(static_cast<double>(p_values.size()) * std::log1p(-p_min));
}

inline double sidak_min_p(std::initializer_list<double> p_values) {
    return sidak_min_p(std::span<const double>(p_values.begin(), p_values.size()));
}

}  // namespace warpcheck::chi2
