// Combining several tests of one check into one p-value, so that a check that
// reports it counts as one test in the run's family. A NaN among the p-values
// gives NaN (and NaN fails).
//  - sidak_min_p: the smallest p-value, Sidak-corrected over the number of
//    tests, 1 - (1 - p_min)^k. Exact for independent tests, conservative for
//    positively correlated ones (tests of the same samples).
//  - weighted_min_p: weighted Bonferroni, min_i p_i / w_i (at most 1) with
//    weights summing to 1: test i rejects at w_i times the level, and the
//    family-wise error stays within the level whatever the dependence.
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

inline double weighted_min_p(std::initializer_list<double> p_values, std::initializer_list<double> weights) {
    double out = 1.0;
    const double* w = weights.begin();
    for (double p : p_values) {
        if (std::isnan(p)) return p;
        const double scaled = p / *w++;
        out = scaled < out ? scaled : out;
    }
    return out;
}

}  // namespace warpcheck::chi2
