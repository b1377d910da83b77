#include "chi2/resolution_test.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "chi2/min_p.h"
#include "chi2/pearson.h"

namespace warpcheck::chi2 {

DigitCounts::DigitCounts(int d) : digits_(d), scale_(std::ldexp(1.0, d)) {
    if (d < 1 || d > kMaxResolutionDigits) throw std::invalid_argument("DigitCounts: needs 1 to 52 digits");
    tables_.assign(static_cast<std::size_t>((d + kTableBits - 1) / kTableBits), {});
}

uint64_t DigitCounts::ones(int k) const {
    if (k < 1 || k > digits_) throw std::out_of_range("DigitCounts::ones: no such digit");
    const int bit = digits_ - k;  // of q
    const auto& table = tables_[static_cast<std::size_t>(bit / kTableBits)];
    const int within = bit % kTableBits;
    uint64_t sum = 0;
    for (std::size_t m = 0; m < table.size(); ++m) sum += ((m >> within) & 1u) ? table[m] : 0;
    return sum;
}

void DigitCounts::merge(const DigitCounts& other) {
    if (other.digits_ != digits_) throw std::invalid_argument("DigitCounts::merge: different numbers of digits");
    n_ += other.n_;
    for (std::size_t t = 0; t < tables_.size(); ++t)
        for (std::size_t m = 0; m < tables_[t].size(); ++m) tables_[t][m] += other.tables_[t][m];
}

ResolutionTest resolution_test(const DigitCounts& counts) {
    ResolutionTest t;
    t.n = counts.n();
    if (counts.n() < 10) {
        t.p_value = std::numeric_limits<double>::quiet_NaN();
        return t;
    }
    t.digits = counts.digits();
    const double n = static_cast<double>(counts.n());
    double smallest = 2.0;
    for (int k = 0; k < counts.digits(); ++k) {
        const double ones = static_cast<double>(counts.ones(k + 1));
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
