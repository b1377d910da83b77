#include "chi2/resolution_test.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "chi2/min_p.h"
#include "chi2/pearson.h"

namespace warpcheck::chi2 {

DigitCounts::DigitCounts(int d) : digits(d) {
    if (d < 1 || d > kMaxResolutionDigits) throw std::invalid_argument("DigitCounts: needs 1 to 52 digits");
}

void DigitCounts::merge(const DigitCounts& other) {
    if (other.digits != digits) throw std::invalid_argument("DigitCounts::merge: different numbers of digits");
    n += other.n;
    for (std::size_t k = 0; k < ones.size(); ++k) ones[k] += other.ones[k];
}

ResolutionTest resolution_test(const DigitCounts& counts) {
    ResolutionTest t;
    t.n = counts.n;
    if (counts.n < 10) {
        t.p_value = std::numeric_limits<double>::quiet_NaN();
        return t;
    }
    t.digits = counts.digits;
    const double n = static_cast<double>(counts.n);
    double smallest = 2.0;
    for (int k = 0; k < counts.digits; ++k) {
        const double ones = static_cast<double>(counts.ones[static_cast<std::size_t>(k)]);
        const double d = 2.0 * ones - n;
        t.statistic.push_back(d * d / n);
        t.p_values.push_back(chi_square_upper_tail(t.statistic.back(), 1.0));
        if (t.p_values.back() < smallest) {
            smallest = t.p_values.back();
            t.worst_digit = k + 1;
            t.worst_ones_fraction = ones / n;
        }
    }
    t.p_value = sidak_min_p(t.p_values);
    return t;
}

ResolutionTest resolution_test(std::span<const double> u, int digits) {
    DigitCounts counts(digits);
    for (double v : u) counts.add(v);
    return resolution_test(counts);
}

}  // namespace warpcheck::chi2
