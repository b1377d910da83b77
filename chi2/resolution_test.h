// Whether values meant to be uniform on [0, 1) are uniform at every resolution
// 2^-k, k = 1 .. digits: the k-th binary digit of u (the bit of weight 2^-k,
// i.e. whether frac(u 2^(k-1)) >= 1/2) must be a fair coin. Each digit is a
// chi-square test of two halves whose edges are multiples of 2^-k, exactly
// representable, so that a float u drawn on the 2^-24 grid (or finer) is
// exactly uniform in them for every k <= 24. A u quantised to 2^-m has every
// digit beyond m equal to 0 and fails at k = m + 1, however uniform its coarse
// histogram looks (a remapped u cut to 10 bits passes Kolmogorov-Smirnov).
// Under uniformity the digits are independent fair coins, so the per-digit
// p-values combine by Sidak's min-p (chi2/min_p.h) exactly: the test gives one
// p-value for the run's family.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace warpcheck::chi2 {

/// The finest resolution tested by default: 2^-20. A float of [0.5, 1) has 4
/// bits below it, so rounding at 2^-24 cannot bias a digit by more than ~2^-4
/// of one value's mass, while a sampler that keeps 20 bits or fewer shows.
inline constexpr int kResolutionDigits = 20;
/// The most digits the counts can hold (a double's significand).
inline constexpr int kMaxResolutionDigits = 52;

/// How many values have each digit set, for a fixed number of digits;
/// mergeable (integer sums: the same counts in any order). The values' top
/// `digits` bits are counted in tables of 11 bits each (two increments per
/// value for 20 digits, instead of one per digit), and the digits' counts
/// are read off the tables.
class DigitCounts {
public:
    explicit DigitCounts(int digits = kResolutionDigits);

    int digits() const { return digits_; }
    uint64_t n() const { return n_; }
    /// Adds u, which must lie in [0, 1) (the caller rejects the rest).
    void add(double u) {
        const auto q = static_cast<uint64_t>(u * scale_);  // exact scaling; q < 2^digits
        ++n_;
        for (std::size_t t = 0; t < tables_.size(); ++t) ++tables_[t][(q >> (t * kTableBits)) & kTableMask];
    }
    /// How many values have digit k (1 .. digits(), the bit of weight 2^-k) set.
    uint64_t ones(int k) const;
    void merge(const DigitCounts& other);

private:
    static constexpr int kTableBits = 11;
    static constexpr uint64_t kTableMask = (uint64_t{1} << kTableBits) - 1;
    int digits_;
    double scale_;  ///< 2^digits
    uint64_t n_ = 0;
    std::vector<std::array<uint64_t, std::size_t{1} << kTableBits>> tables_;
};

struct ResolutionTest {
    int digits = 0;                  ///< digits tested
    uint64_t n = 0;                  ///< values
    std::vector<double> statistic;   ///< per digit k = 1..digits: (2 ones - n)^2 / n, chi-square with 1 dof
    std::vector<double> p_values;    ///< per digit
    double p_value = 0.0;            ///< Sidak min-p over the digits; NaN when nothing could be tested
    int worst_digit = 0;             ///< the digit of the smallest p-value (1-based; 0 when none)
    double worst_ones_fraction = 0;  ///< that digit's share of ones
};

/// The test of the counts. Fewer than 10 values (fewer than 5 expected per
/// half) test nothing: p_value NaN, digits 0.
ResolutionTest resolution_test(const DigitCounts& counts);
/// The same of a set of values in [0, 1).
ResolutionTest resolution_test(std::span<const double> u, int digits = kResolutionDigits);

}  // namespace warpcheck::chi2
