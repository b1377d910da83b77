#include "chi2/unbinned.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace warpcheck::chi2 {
namespace {

// Stephens' finite-n scalings of the statistics onto their asymptotic laws
// (M. A. Stephens, "Use of the Kolmogorov-Smirnov, Cramer-von Mises and related
// statistics without extensive tables", J. R. Statist. Soc. B 32 (1970)
// 115-122; also Numerical Recipes, 3rd ed., section 14.3): the tail of
// (sqrt(n) + 0.12 + 0.11/sqrt(n)) D is Q_K, that of
// (sqrt(n) + 0.155 + 0.24/sqrt(n)) V is Q_V, to about 1% for n >= 4.
double ks_scale(std::size_t n) {
    const double r = std::sqrt(static_cast<double>(n));
    return r + 0.12 + 0.11 / r;
}
double kuiper_scale(std::size_t n) {
    const double r = std::sqrt(static_cast<double>(n));
    return r + 0.155 + 0.24 / r;
}

// Marsaglia and Marsaglia's approximation of the asymptotic A^2 upper tail,
// written from the formula of G. Marsaglia and J. Marsaglia, "Evaluating the
// Anderson-Darling distribution", J. Statistical Software 9(2) (2004), function
// adinf: max |error| < 2e-6 for z < 2 and < 8e-7 above (their figures). The
// upper tail is formed directly (expm1) so that small p-values keep their
// relative precision instead of being 1 - (a number near 1).
double ad_asymptotic_upper_tail(double z) {
    if (!(z > 0.0)) return 1.0;
    if (z < 2.0) {
        const double poly =
            2.00012 + (0.247105 - (0.0649821 - (0.0347962 - (0.011672 - 0.00168691 * z) * z) * z) * z) * z;
        return 1.0 - std::exp(-1.2337141 / z) / std::sqrt(z) * poly;
    }
    const double inner = 1.0776 - (2.30695 - (0.43424 - (0.082433 - (0.008056 - 0.0003146 * z) * z) * z) * z) * z;
    return -std::expm1(-std::exp(inner));
}

// Marsaglia and Marsaglia's (2004, function errfix) correction of the
// asymptotic CDF value x for n samples: P(A^2 <= z) = x + errfix(n, x), with
// |error| < 2e-6 for n >= 5 by their account. At n = 10^6 it is below 1e-7.
// Its polynomial for x > 0.8 is -6e-4 / n rather than 0 at x = 1, so p-values
// bottom out at 6e-4 / n (6e-10 at 10^6): harmless, far below any level used.
double ad_errfix(double n, double x) {
    if (x > 0.8)
        return (-130.2137 + (745.2337 - (1705.091 - (1950.646 - (1116.360 - 255.7844 * x) * x) * x) * x) * x) / n;
    const double c = 0.01265 + 0.1757 / n;
    if (x < c) {
        double t = x / c;
        t = std::sqrt(t) * (1.0 - t) * (49.0 * t - 102.0);
        return t * (0.0037 / (n * n) + 0.00078 / n + 0.00006) / n;
    }
    double t = (x - c) / (0.8 - c);
    t = -0.00022633 + (6.54034 - (14.6538 - (14.458 - (8.259 - 1.91864 * t) * t) * t) * t) * t;
    return t * (0.04213 / n + 0.01365 / (n * n));
}

double clamp_probability(double p) { return std::isnan(p) ? p : std::clamp(p, 0.0, 1.0); }

// Largest x of [lo, hi] with upper_tail(x) >= level, for a decreasing tail.
template <typename Tail>
double invert_tail(Tail upper_tail, double level, double lo, double hi) {
    for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        (upper_tail(mid) >= level ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

}  // namespace

std::string_view short_name(UnbinnedTest test) {
    switch (test) {
        case UnbinnedTest::KolmogorovSmirnov: return "ks";
        case UnbinnedTest::Kuiper: return "kuiper";
        case UnbinnedTest::AndersonDarling: return "ad";
    }
    return "?";
}

double UnbinnedStatistics::statistic(UnbinnedTest test) const {
    switch (test) {
        case UnbinnedTest::KolmogorovSmirnov: return ks();
        case UnbinnedTest::Kuiper: return kuiper();
        case UnbinnedTest::AndersonDarling: return ad;
    }
    return std::nan("");
}

double UnbinnedStatistics::p_value(UnbinnedTest test) const {
    if (n == 0) return std::nan("");
    switch (test) {
        case UnbinnedTest::KolmogorovSmirnov: return kolmogorov_q(ks_scale(n) * ks());
        case UnbinnedTest::Kuiper: return kuiper_q(kuiper_scale(n) * kuiper());
        case UnbinnedTest::AndersonDarling: {
            if (std::isnan(ad)) return ad;
            const double tail = ad_asymptotic_upper_tail(ad);
            return clamp_probability(tail - ad_errfix(static_cast<double>(n), 1.0 - tail));
        }
    }
    return std::nan("");
}

namespace {

/// The value's 20-bit key floor(u 2^20), clamped into [0, 2^20).
uint32_t unit_key(double u) {
    // Truncation is floor for u >= 0; values are in [0, 1], so only u = 1 needs the clamp.
    return std::min(static_cast<uint32_t>(u * 0x1p20), (uint32_t{1} << 20) - 1);
}

/// Where each bucket of 10 bits of the key starts: 1024 starts and the end.
using BucketStarts = std::array<std::size_t, 1025>;

/// One stable counting-sort pass of `from` into `to` by 10 bits of the key.
void radix_pass(const std::vector<double>& from, std::vector<double>& to, BucketStarts& start, int shift) {
    for (double u : from) to[start[(unit_key(u) >> shift) & 1023u]++] = u;
}

}  // namespace

void sort_unit_values(std::vector<double>& values) {
    // LSD radix sort on the 20-bit key (two passes of 1024 buckets: each pass
    // writes 1024 sequential streams, which stay in cache), both passes'
    // buckets counted in one read. About 3 times faster than std::sort at 10^6
    // values.
    BucketStarts low{}, high{};
    for (double u : values) {
        const uint32_t key = unit_key(u);
        ++low[(key & 1023u) + 1];
        ++high[(key >> 10) + 1];
    }
    for (std::size_t b = 0; b < 1024; ++b) {
        low[b + 1] += low[b];
        high[b + 1] += high[b];
    }
    std::vector<double> tmp(values.size());
    radix_pass(values, tmp, low, 0);
    radix_pass(tmp, values, high, 10);
    // Then insertion sort, which only has to order values that share a key
    // (~1 per key for values spread over [0, 1]). A wrong warp may put most of
    // its values under one key: past 8 moves per value, std::sort finishes.
    const std::size_t budget = 8 * values.size();
    std::size_t moves = 0;
    for (std::size_t i = 1; i < values.size() && moves <= budget; ++i)
        for (std::size_t j = i; j > 0 && values[j] < values[j - 1]; --j, ++moves) std::swap(values[j], values[j - 1]);
    if (moves > budget) std::sort(values.begin(), values.end());
}

namespace {

/// A^2's logarithms see transforms clamped to [kLo, kHi]: a sample exactly at
/// an end of the support costs a finite amount instead of an infinity.
constexpr double kLo = 1e-300, kHi = 1.0 - 0x1p-53;

/// The integral over [s, e] of (c - t)^2 / (t (1 - t)) dt, which is
/// c^2 / t + (1 - c)^2 / (1 - t) - 1 in partial fractions (A^2's integrand for
/// an empirical CDF that stays at c on [s, e]), with the ends clamped as in
/// unbinned_statistics. log1p keeps the precision of narrow pieces.
double ad_piece(double c, double s, double e) {
    s = std::clamp(s, kLo, kHi);
    e = std::clamp(e, kLo, kHi);
    if (!(e > s)) return 0.0;
    const double w = e - s;
    return c * c * std::log1p(w / s) + (1.0 - c) * (1.0 - c) * std::log1p(w / (1.0 - e)) - w;
}

}  // namespace

UnbinnedStatistics banded_statistics(std::span<const double> lo, std::span<const double> hi) {
    UnbinnedStatistics s;
    s.n = lo.size();
    if (lo.empty() || hi.size() != lo.size()) return s;
    const std::size_t count = lo.size();
    const double n = static_cast<double>(count);
    for (std::size_t k = 0; k < count; ++k) {
        if (std::isnan(lo[k]) || std::isnan(hi[k])) {
            s.d_plus = s.d_minus = s.ad = std::nan("");
            return s;
        }
        s.d_plus = std::max(s.d_plus, static_cast<double>(k + 1) / n - hi[k]);
        s.d_minus = std::max(s.d_minus, lo[k] - static_cast<double>(k) / n);
    }
    // A^2: walk the breakpoints of the envelope [#{hi <= t} / n, #{lo <= t} / n]
    // (the upper ends raise its lower edge, the lower ends its upper edge); on
    // each piece between them the distance from t to the envelope is t's
    // distance to one constant edge or 0.
    double sum = 0.0, t = 0.0;
    std::size_t i = 0, j = 0;  // #{hi <= t}, #{lo <= t}
    while (t < 1.0) {
        while (i < count && hi[i] <= t) ++i;
        while (j < count && lo[j] <= t) ++j;
        const double e = std::min({i < count ? hi[i] : 1.0, j < count ? lo[j] : 1.0, 1.0});
        const double below = static_cast<double>(i) / n, above = static_cast<double>(j) / n;
        if (t < below) sum += ad_piece(below, t, std::min(e, below));
        if (e > above) sum += ad_piece(above, std::max(t, above), e);
        if (!(e > t)) break;  // only values above 1 remain
        t = e;
    }
    s.ad = n * sum;
    return s;
}

UnbinnedStatistics unbinned_statistics(std::span<const double> u) {
    UnbinnedStatistics s;
    s.n = u.size();
    if (u.empty()) return s;
    const double n = static_cast<double>(u.size());
    double ad_sum = 0.0;
    for (std::size_t i = 0; i < u.size(); ++i) {
        const double k = static_cast<double>(i);
        s.d_plus = std::max(s.d_plus, (k + 1.0) / n - u[i]);
        s.d_minus = std::max(s.d_minus, u[i] - k / n);
        // Anderson and Darling's computing form:
        // A^2 = -n - (1/n) sum_i (2i - 1) [ln u_(i) + ln(1 - u_(n+1-i))].
        const double lo = std::clamp(u[i], kLo, kHi);
        const double hi = std::clamp(u[u.size() - 1 - i], kLo, kHi);
        ad_sum += (2.0 * k + 1.0) * (std::log(lo) + std::log1p(-hi));
        if (std::isnan(u[i])) s.d_plus = s.d_minus = ad_sum = std::nan("");
    }
    s.ad = -n - ad_sum / n;
    return s;
}

// Kolmogorov's limit law (A. Kolmogorov, Giornale dell'Istituto Italiano degli
// Attuari 4 (1933) 83-91): Q_K(l) = 2 sum_{j>=1} (-1)^(j-1) exp(-2 j^2 l^2).
// Below l = 1.18 the alternating series converges slowly, and the equivalent
// Jacobi theta form P(K <= l) = sqrt(2 pi)/l sum_{j>=1} exp(-(2j-1)^2 pi^2 / (8 l^2))
// is used instead (both as in Numerical Recipes, 3rd ed., section 6.14).
double kolmogorov_q(double lambda) {
    if (std::isnan(lambda)) return lambda;
    if (lambda <= 0.0) return 1.0;
    if (lambda < 1.18) {
        const double y = std::exp(-std::numbers::pi * std::numbers::pi / (8.0 * lambda * lambda));
        double sum = 0.0;
        for (int j = 1; j <= 40; ++j) sum += std::pow(y, (2.0 * j - 1.0) * (2.0 * j - 1.0));
        return clamp_probability(1.0 - std::sqrt(2.0 * std::numbers::pi) / lambda * sum);
    }
    double sum = 0.0;
    for (int j = 1; j <= 100; ++j) {
        const double term = std::exp(-2.0 * j * j * lambda * lambda);
        sum += (j % 2 == 1 ? term : -term);
        if (term < 1e-300) break;
    }
    return clamp_probability(2.0 * sum);
}

// Kuiper's limit law (N. H. Kuiper, Proc. Koninklijke Nederlandse Akademie van
// Wetenschappen A 63 (1960) 38-47): Q_V(l) = 2 sum_{j>=1} (4 j^2 l^2 - 1)
// exp(-2 j^2 l^2); below l = 0.4 the tail is 1 to double precision
// (Numerical Recipes, 3rd ed., section 6.14).
double kuiper_q(double lambda) {
    if (std::isnan(lambda)) return lambda;
    if (lambda < 0.4) return 1.0;
    double sum = 0.0;
    for (int j = 1; j <= 100; ++j) {
        const double j2l2 = static_cast<double>(j) * j * lambda * lambda;
        const double term = (4.0 * j2l2 - 1.0) * std::exp(-2.0 * j2l2);
        sum += term;
        if (std::abs(term) < 1e-300) break;
    }
    return clamp_probability(2.0 * sum);
}

double anderson_darling_asymptotic_cdf(double z) { return 1.0 - ad_asymptotic_upper_tail(z); }

double anderson_darling_cdf(std::size_t n, double z) {
    const double x = anderson_darling_asymptotic_cdf(z);
    return clamp_probability(x + ad_errfix(static_cast<double>(n), x));
}

double asymptotic_critical_value(UnbinnedTest test, double level) {
    switch (test) {
        case UnbinnedTest::KolmogorovSmirnov: return invert_tail(kolmogorov_q, level, 0.1, 20.0);
        case UnbinnedTest::Kuiper: return invert_tail(kuiper_q, level, 0.4, 20.0);
        case UnbinnedTest::AndersonDarling: return invert_tail(ad_asymptotic_upper_tail, level, 1e-3, 400.0);
    }
    return std::nan("");
}

}  // namespace warpcheck::chi2
