#include "chi2/power.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <random>
#include <tuple>
#include <vector>

#include <Eigen/Core>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/non_central_chi_squared.hpp>

namespace warpcheck::chi2 {
namespace {

constexpr int kBridges = 1000;
constexpr int kGrid = 512;

/// kBridges Brownian bridges at t = j / kGrid, j = 1 .. kGrid - 1, one per
/// column, from a fixed mt19937_64 stream (its sequence is fixed by the
/// standard) through Box-Muller written out here (std::normal_distribution is
/// not portable).
const Eigen::ArrayXXf& bridges() {
    static const Eigen::ArrayXXf b = [] {
        std::mt19937_64 rng(20040101);
        auto uniform = [&rng] { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1p-53; };
        std::vector<double> w(kGrid + 1);
        Eigen::ArrayXXf out(kGrid - 1, kBridges);
        const double step = std::sqrt(1.0 / kGrid);
        for (int r = 0; r < kBridges; ++r) {
            w[0] = 0.0;
            for (int j = 1; j <= kGrid; j += 2) {
                const double radius = std::sqrt(-2.0 * std::log(uniform())), angle = 2.0 * std::numbers::pi * uniform();
                w[j] = w[j - 1] + step * radius * std::cos(angle);
                if (j + 1 <= kGrid) w[j + 1] = w[j] + step * radius * std::sin(angle);
            }
            for (int j = 1; j < kGrid; ++j)
                out(j - 1, r) = static_cast<float>(w[j] - static_cast<double>(j) / kGrid * w[kGrid]);
        }
        return out;
    }();
    return b;
}

/// u (1 - u) at the grid's points: the drift's shape and the Anderson-Darling weight.
const Eigen::ArrayXd& grid_weight() {
    static const Eigen::ArrayXd w = [] {
        const Eigen::ArrayXd u = Eigen::ArrayXd::LinSpaced(kGrid - 1, 1, kGrid - 1) / kGrid;
        return Eigen::ArrayXd(u * (1.0 - u));
    }();
    return w;
}

/// The asymptotic statistic of one bridge plus the drift delta u (1 - u).
/// Eigen sums the Anderson-Darling terms in SIMD lanes, not in grid order: the
/// last bits may differ from a loop's, but the power only counts bridges beyond
/// the critical value, and no figure of validate --all changes.
double drifted_statistic(UnbinnedTest test, const Eigen::ArrayXXf::ConstColXpr& bridge, double delta) {
    const Eigen::ArrayXd y = bridge.cast<double>() + delta * grid_weight();
    // The sup of a bridge on a grid of step 1/kGrid falls short of the
    // continuous sup by ~beta sqrt(1/kGrid), beta = -zeta(1/2)/sqrt(2 pi)
    // = 0.5826 (Broadie, Glasserman and Kou's continuity correction for
    // discretely monitored extrema); each extreme is moved out by that, so
    // the simulated power is the continuous statistic's, not a conservative one.
    static const double shift = 0.5826 * std::sqrt(1.0 / kGrid);
    const double hi = std::max(0.0, y.maxCoeff()), lo = std::min(0.0, y.minCoeff());
    switch (test) {
        case UnbinnedTest::KolmogorovSmirnov: return std::max(hi, -lo) + shift;
        case UnbinnedTest::Kuiper: return hi - lo + 2.0 * shift;
        case UnbinnedTest::AndersonDarling: return (y.square() / grid_weight()).sum() / kGrid;
    }
    return std::nan("");
}

double simulated_power(UnbinnedTest test, double critical, double delta) {
    const Eigen::ArrayXXf& b = bridges();
    int hits = 0;
    for (int r = 0; r < kBridges; ++r) hits += drifted_statistic(test, b.col(r), delta) > critical;
    return static_cast<double>(hits) / kBridges;
}

/// The drift sqrt(n) eps at which the simulated power reaches `power`.
double drift_for_power(UnbinnedTest test, double level, double power) {
    const double critical = asymptotic_critical_value(test, level);
    double lo = 0.0, hi = 128.0;
    for (int i = 0; i < 20; ++i) {  // to 1e-4 of the range: far below the simulation's ~1.5% noise
        const double mid = 0.5 * (lo + hi);
        (simulated_power(test, critical, mid) >= power ? hi : lo) = mid;
    }
    return hi;
}

}  // namespace

double pearson_noncentrality_for_power(double dof, double level, double power) {
    if (!(dof >= 1.0) || !(level > 0.0 && level < 1.0) || !(power > level && power < 1.0)) return std::nan("");
    const boost::math::chi_squared null(dof);
    const double critical = boost::math::quantile(boost::math::complement(null, level));
    // The lambda at which the noncentral CDF at the critical value is 1 - power.
    return boost::math::non_central_chi_squared::find_non_centrality(dof, critical, 1.0 - power);
}

double pearson_tilt_for_noncentrality(double lambda, uint64_t n) {
    return std::sqrt(3.0 * lambda / static_cast<double>(n));
}

double unbinned_tilt_for_power(UnbinnedTest test, double level, uint64_t n, double power) {
    if (!(level > 0.0 && level < 1.0) || !(power > level && power < 1.0) || n == 0) return std::nan("");
    static std::mutex mutex;
    static std::map<std::tuple<UnbinnedTest, double, double>, double> cache;
    const auto key = std::make_tuple(test, level, power);
    double drift = 0.0;
    {
        const std::lock_guard<std::mutex> lock(mutex);
        const auto it = cache.find(key);
        if (it != cache.end()) {
            drift = it->second;
        } else {
            drift = drift_for_power(test, level, power);
            cache.emplace(key, drift);
        }
    }
    return drift / std::sqrt(static_cast<double>(n));
}

}  // namespace warpcheck::chi2
