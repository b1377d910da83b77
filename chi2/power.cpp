#include "chi2/power.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <random>
#include <tuple>
#include <utility>
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

/// The asymptotic statistic of one bridge plus the drift delta u (1 - u),
/// its values y written to `y` (kGrid - 1 of them, reused across calls: this
/// runs 20 x kBridges times per test and level, in every process that states
/// an unbinned power, and an allocation per call cost more than the sums).
/// The extremes are exact whatever the order; Eigen sums the Anderson-Darling
/// terms in SIMD lanes, not in grid order: the last bits may differ from a
/// loop's, but the power only counts bridges beyond the critical value, and no
/// figure of validate --all changes.
double drifted_statistic(UnbinnedTest test, const Eigen::ArrayXXf::ConstColXpr& bridge, double delta,
                         Eigen::ArrayXd& y) {
    // The sup of a bridge on a grid of step 1/kGrid falls short of the
    // continuous sup by ~beta sqrt(1/kGrid), beta = -zeta(1/2)/sqrt(2 pi)
    // = 0.5826 (Broadie, Glasserman and Kou's continuity correction for
    // discretely monitored extrema); each extreme is moved out by that, so
    // the simulated power is the continuous statistic's, not a conservative one.
    static const double shift = 0.5826 * std::sqrt(1.0 / kGrid);
    const Eigen::ArrayXd& w = grid_weight();
    if (test == UnbinnedTest::AndersonDarling) {
        y = bridge.cast<double>() + delta * w;
        return (y.square() / w).sum() / kGrid;
    }
    // Plain loops: the same sums (b + delta w, rounded once each) as Eigen's
    // expression, without its per-element calls in unoptimised builds.
    const float* b = bridge.data();
    const double* weight = w.data();
    double hi = 0.0, lo = 0.0;
    for (int j = 0; j < kGrid - 1; ++j) {
        const double v = static_cast<double>(b[j]) + delta * weight[j];
        hi = std::max(hi, v);
        lo = std::min(lo, v);
    }
    switch (test) {
        case UnbinnedTest::KolmogorovSmirnov: return std::max(hi, -lo) + shift;
        case UnbinnedTest::Kuiper: return hi - lo + 2.0 * shift;
        case UnbinnedTest::AndersonDarling: break;
    }
    return std::nan("");
}

/// Whether the simulated power, the share of the kBridges bridges whose
/// statistic exceeds `critical`, is at least `power`: the bridges are counted
/// only until that is decided (the answer is the full count's).
bool reaches_power(UnbinnedTest test, double critical, double delta, double power) {
    int needed = 0;  // the fewest hits h with h / kBridges >= power, as the share is compared
    while (needed <= kBridges && !(static_cast<double>(needed) / kBridges >= power)) ++needed;
    const Eigen::ArrayXXf& b = bridges();
    Eigen::ArrayXd y(kGrid - 1);
    int hits = 0;
    for (int r = 0; r < kBridges; ++r) {
        if (hits >= needed) return true;
        if (hits + (kBridges - r) < needed) return false;
        hits += drifted_statistic(test, b.col(r), delta, y) > critical;
    }
    return hits >= needed;
}

/// The drift sqrt(n) eps at which the simulated power reaches `power`.
double drift_for_power(UnbinnedTest test, double level, double power) {
    const double critical = asymptotic_critical_value(test, level);
    double lo = 0.0, hi = 128.0;
    for (int i = 0; i < 20; ++i) {  // to 1e-4 of the range: far below the simulation's ~1.5% noise
        const double mid = 0.5 * (lo + hi);
        (reaches_power(test, critical, mid, power) ? hi : lo) = mid;
    }
    return hi;
}

}  // namespace

double pearson_noncentrality_for_power(double dof, double level, double power, double band_noncentrality) {
    if (!(dof >= 1.0) || !(level > 0.0 && level < 1.0) || !(power > level && power < 1.0) ||
        !(band_noncentrality >= 0.0) || !std::isfinite(band_noncentrality))
        return std::nan("");
    double critical = 0.0;
    if (band_noncentrality > 0.0) {
        const boost::math::non_central_chi_squared banded(dof, band_noncentrality);
        critical = boost::math::quantile(boost::math::complement(banded, level));
    } else {
        const boost::math::chi_squared null(dof);
        critical = boost::math::quantile(boost::math::complement(null, level));
    }
    // The lambda at which the noncentral CDF at the critical value is 1 - power.
    return boost::math::non_central_chi_squared::find_non_centrality(dof, critical, 1.0 - power);
}

std::vector<double> tilt_gradient(const Binning& b, std::span<const double> probability, int axis) {
    const std::size_t cells = b.cell_count();
    std::vector<double> g(cells, 0.0);
    if (probability.size() != cells) return g;
    double total = 0.0;
    for (double p : probability) total += std::max(p, 0.0);
    if (!(total > 0.0)) return g;
    const auto p = [&](std::size_t c) { return std::max(probability[c], 0.0) / total; };
    const std::size_t cols = static_cast<std::size_t>(b.cols()), rows = static_cast<std::size_t>(b.rows());
    if (b.parameter_dimension() == 1 || axis == 1) {
        // Along the line (its cells in order) or along v (rows in order): F
        // runs from a to a + P over a part of probability P, and its mean
        // 2F - 1 there is 2a + P - 1.
        const bool line = b.parameter_dimension() == 1;
        const std::size_t parts = line ? cols : rows;
        double below = 0.0;
        for (std::size_t j = 0; j < parts; ++j) {
            double part = 0.0;
            if (line) part = p(j);
            else
                for (std::size_t c = 0; c < cols; ++c) part += p(j * cols + c);
            const double mean = 2.0 * below + part - 1.0;
            if (line) g[j] = p(j) * mean;
            else
                for (std::size_t c = 0; c < cols; ++c) g[j * cols + c] = p(j * cols + c) * mean;
            below += part;
        }
        return g;
    }
    // Along u in 2D: F(u) = sum over cells of p times the share of the cell's
    // u range below u, piecewise linear between the cells' u edges; a cell's
    // mean of F by Simpson's rule on its range. F is swept once over the
    // sorted edges (slope p / width between a cell's ends).
    std::vector<ParamRect> rect(cells);
    std::vector<std::pair<double, double>> slope_change;  // (u, change of dF/du)
    for (std::size_t c = 0; c < cells; ++c) {
        rect[c] = b.cell_rect(c);
        const double w = rect[c].u1 - rect[c].u0;
        if (!(w > 0.0)) continue;
        slope_change.push_back({rect[c].u0, p(c) / w});
        slope_change.push_back({rect[c].u1, -p(c) / w});
    }
    std::sort(slope_change.begin(), slope_change.end());
    std::vector<std::pair<double, std::size_t>> at;  // (u, 3 c + k): the three Simpson points of each cell
    for (std::size_t c = 0; c < cells; ++c) {
        at.push_back({rect[c].u0, 3 * c});
        at.push_back({0.5 * (rect[c].u0 + rect[c].u1), 3 * c + 1});
        at.push_back({rect[c].u1, 3 * c + 2});
    }
    std::sort(at.begin(), at.end());
    std::vector<double> F(3 * cells, 0.0);
    double value = 0.0, slope = 0.0, position = slope_change.empty() ? 0.0 : slope_change.front().first;
    std::size_t k = 0;
    for (const auto& [u, index] : at) {
        while (k < slope_change.size() && slope_change[k].first <= u) {
            value += slope * (slope_change[k].first - position);
            position = slope_change[k].first;
            slope += slope_change[k].second;
            ++k;
        }
        F[index] = value + slope * (u - position);
    }
    for (std::size_t c = 0; c < cells; ++c) {
        const double mean = (F[3 * c] + 4.0 * F[3 * c + 1] + F[3 * c + 2]) / 6.0;
        g[c] = p(c) * (2.0 * mean - 1.0);
    }
    return g;
}

namespace {

/// Sums of gradient and probability over the terms that pooling made.
std::pair<std::vector<double>, std::vector<double>> per_term(std::span<const double> gradient,
                                                             std::span<const double> probability,
                                                             std::span<const std::size_t> term_of_cell) {
    std::size_t terms = 0;
    for (std::size_t t : term_of_cell)
        if (t != static_cast<std::size_t>(-1)) terms = std::max(terms, t + 1);
    std::vector<double> moved(terms, 0.0), mass(terms, 0.0);
    for (std::size_t c = 0; c < probability.size(); ++c) {
        const std::size_t t = term_of_cell[c];
        if (t >= terms) continue;
        moved[t] += gradient[c];
        mass[t] += std::max(probability[c], 0.0);
    }
    return {std::move(moved), std::move(mass)};
}

}  // namespace

double tilt_noncentrality(std::span<const double> gradient, std::span<const double> probability,
                          std::span<const std::size_t> term_of_cell, uint64_t samples) {
    if (gradient.size() != probability.size() || term_of_cell.size() != probability.size()) return std::nan("");
    const auto [moved, mass] = per_term(gradient, probability, term_of_cell);
    double sum = 0.0;
    for (std::size_t t = 0; t < moved.size(); ++t)
        if (mass[t] > 0.0) sum += moved[t] * moved[t] / mass[t];
    return static_cast<double>(samples) * sum;
}

double tilt_mean_shift(std::span<const double> gradient, std::span<const double> probability,
                       std::span<const std::size_t> term_of_cell) {
    if (gradient.size() != probability.size() || term_of_cell.size() != probability.size()) return std::nan("");
    const auto [moved, mass] = per_term(gradient, probability, term_of_cell);
    double sum = 0.0;
    for (std::size_t t = 0; t < moved.size(); ++t)
        if (mass[t] > 0.0) sum += moved[t] / mass[t];
    return sum;
}

double tilt_for_noncentrality(double lambda, double per_unit, double shift) {
    if (!(lambda >= 0.0) || std::isnan(shift)) return std::nan("");
    if (!(per_unit > 0.0)) return std::numeric_limits<double>::infinity();
    const double b = std::abs(shift);
    return (b + std::sqrt(b * b + 4.0 * per_unit * lambda)) / (2.0 * per_unit);
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
