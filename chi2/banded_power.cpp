#include "chi2/banded_power.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace warpcheck::chi2 {
namespace {

constexpr int kBandedBridges = 1000;
constexpr int kBandedGrid = 512;

/// kBandedBridges Brownian bridges at u = j / kBandedGrid, j = 1 .. kBandedGrid - 1, bridge r at
/// [r * (kBandedGrid - 1), (r + 1) * (kBandedGrid - 1)), from a fixed mt19937_64 stream
/// through Box-Muller (std::normal_distribution is not portable).
const std::vector<double>& banded_bridges() {
    static const std::vector<double> b = [] {
        std::mt19937_64 rng(20260101);
        auto uniform = [&rng] { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1p-53; };
        std::vector<double> w(kBandedGrid + 1), out;
        out.reserve(static_cast<std::size_t>(kBandedBridges) * (kBandedGrid - 1));
        const double step = std::sqrt(1.0 / kBandedGrid);
        for (int r = 0; r < kBandedBridges; ++r) {
            w[0] = 0.0;
            for (int j = 1; j <= kBandedGrid; j += 2) {
                const double radius = std::sqrt(-2.0 * std::log(uniform())), angle = 2.0 * std::numbers::pi * uniform();
                w[j] = w[j - 1] + step * radius * std::cos(angle);
                if (j + 1 <= kBandedGrid) w[j + 1] = w[j] + step * radius * std::sin(angle);
            }
            for (int j = 1; j < kBandedGrid; ++j) out.push_back(w[j] - static_cast<double>(j) / kBandedGrid * w[kBandedGrid]);
        }
        return out;
    }();
    return b;
}

/// u (1 - u) at the grid's points u = j / kBandedGrid, j = 1 .. kBandedGrid - 1.
const std::vector<double>& banded_weights() {
    static const std::vector<double> w = [] {
        std::vector<double> out;
        for (int j = 1; j < kBandedGrid; ++j) {
            const double u = static_cast<double>(j) / kBandedGrid;
            out.push_back(u * (1.0 - u));
        }
        return out;
    }();
    return w;
}

/// The banded statistic of one bridge (its kBandedGrid - 1 values from `bridge`)
/// plus the drift delta u (1 - u), against the band [-c, c].
double banded_statistic(UnbinnedTest test, const double* bridge, double delta, double c) {
    // The grid's extremes fall short of the continuous ones by ~0.5826 / sqrt(kBandedGrid)
    // (the continuity correction of chi2/power.cpp).
    static const double correction = 0.5826 * std::sqrt(1.0 / kBandedGrid);
    const double* weight = banded_weights().data();
    if (test == UnbinnedTest::AndersonDarling) {
        // In grid order, as the sum always was; a term outside the band adds 0.
        double ad = 0.0;
        for (int j = 0; j < kBandedGrid - 1; ++j) {
            const double d = std::abs(bridge[j] + delta * weight[j]) - c;
            if (d > 0.0) ad += d * d / weight[j];
        }
        return ad / kBandedGrid;
    }
    double hi = 0.0, lo = 0.0;
    for (int j = 0; j < kBandedGrid - 1; ++j) {
        const double y = bridge[j] + delta * weight[j];
        hi = std::max(hi, y);
        lo = std::min(lo, y);
    }
    const double d_plus = std::max(0.0, hi + correction - c), d_minus = std::max(0.0, -lo + correction - c);
    return test == UnbinnedTest::Kuiper ? d_plus + d_minus : std::max(d_plus, d_minus);
}

/// Whether the simulated power, the share of the kBandedBridges bridges whose
/// statistic exceeds `critical`, is at least `power`: the bridges are counted
/// only until that is decided (the answer is the full count's).
bool reaches_power(UnbinnedTest test, double critical, double delta, double c, double power) {
    int needed = 0;  // the fewest hits h with h / kBandedBridges >= power, as the share is compared
    while (needed <= kBandedBridges && !(static_cast<double>(needed) / kBandedBridges >= power)) ++needed;
    const std::vector<double>& b = banded_bridges();
    int hits = 0;
    for (int r = 0; r < kBandedBridges; ++r) {
        if (hits >= needed) return true;
        if (hits + (kBandedBridges - r) < needed) return false;
        hits += banded_statistic(test, b.data() + static_cast<std::size_t>(r) * (kBandedGrid - 1), delta, c) > critical;
    }
    return hits >= needed;
}

}  // namespace

void prepare_banded_power() { (void)banded_bridges(); }

double banded_tilt_for_power(UnbinnedTest test, double level, double shift, uint64_t n, double power) {
    if (!(level > 0.0 && level < 1.0) || !(power > level && power < 1.0) || n == 0 || !(shift >= 0.0))
        return std::nan("");
    const double critical = asymptotic_critical_value(test, level);
    const double root_n = std::sqrt(static_cast<double>(n)), c = root_n * shift;
    constexpr double kMaxDrift = 512.0;
    if (!reaches_power(test, critical, kMaxDrift, c, power)) return std::nan("");
    double lo = 0.0, hi = kMaxDrift;
    for (int i = 0; i < 24; ++i) {  // to 3e-5 of the range: far below the simulation's ~1.5% noise
        const double mid = 0.5 * (lo + hi);
        (reaches_power(test, critical, mid, c, power) ? hi : lo) = mid;
    }
    return hi / root_n;
}

}  // namespace warpcheck::chi2
