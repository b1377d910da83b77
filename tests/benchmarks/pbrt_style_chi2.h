// The reference of the chi-square benchmark: the procedure pbrt-v4 publishes
// for testing its spherical warps, rebuilt here from its description (no pbrt
// code): 80 x 160 (theta, phi) cells; sample counts by cell; expected counts
// from the pdf times sin(theta) integrated over each cell by nested adaptive
// Simpson (theta outside, phi inside, tolerance 1e-6, depth 6); cells with an
// expected count below 5 pooled into one; Pearson's statistic and its p-value.
// Single-threaded, double-precision, one sample at a time, as described.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>

namespace warpcheck::bench {

constexpr int kPbrtThetaRes = 80, kPbrtPhiRes = 160;

/// Adaptive Simpson on [a, b] with tolerance eps and at most `depth` halvings.
template <typename F>
double adaptive_simpson(const F& f, double a, double b, double eps, int depth) {
    auto step = [&](auto&& self, double lo, double hi, double fa, double fm, double fb, double whole, double tol,
                    int d) -> double {
        const double m = 0.5 * (lo + hi), lm = 0.5 * (lo + m), rm = 0.5 * (m + hi);
        const double flm = f(lm), frm = f(rm);
        const double left = (m - lo) / 6 * (fa + 4 * flm + fm), right = (hi - m) / 6 * (fm + 4 * frm + fb);
        const double both = left + right;
        if (d <= 0 || std::abs(both - whole) <= 15 * tol) return both + (both - whole) / 15;
        return self(self, lo, m, fa, flm, fm, left, tol / 2, d - 1) +
               self(self, m, hi, fm, frm, fb, right, tol / 2, d - 1);
    };
    const double fa = f(a), fb = f(b), fm = f(0.5 * (a + b));
    return step(step, a, b, fa, fm, fb, (b - a) / 6 * (fa + 4 * fm + fb), eps, depth);
}

/// The p-value of `samples` draws of `sample(u0, u1) -> (x, y, z)` against
/// `pdf(x, y, z)` (per solid angle), uniform inputs from `next_float()`.
template <typename Rng, typename Sample, typename Pdf>
double pbrt_style_chi2(Rng& rng, uint64_t samples, const Sample& sample, const Pdf& pdf) {
    constexpr double kPi = std::numbers::pi;
    std::vector<double> observed(kPbrtThetaRes * kPbrtPhiRes, 0.0), expected(observed.size());
    for (uint64_t i = 0; i < samples; ++i) {
        const float u0 = rng.next_float(), u1 = rng.next_float();
        const auto [x, y, z] = sample(u0, u1);
        const double theta = std::acos(std::clamp(static_cast<double>(z), -1.0, 1.0));
        double phi = std::atan2(static_cast<double>(y), static_cast<double>(x));
        if (phi < 0) phi += 2 * kPi;
        const int t = std::min(static_cast<int>(theta * kPbrtThetaRes / kPi), kPbrtThetaRes - 1);
        const int p = std::min(static_cast<int>(phi * kPbrtPhiRes / (2 * kPi)), kPbrtPhiRes - 1);
        observed[static_cast<std::size_t>(t * kPbrtPhiRes + p)] += 1;
    }
    for (int t = 0; t < kPbrtThetaRes; ++t) {
        const double t0 = t * kPi / kPbrtThetaRes, t1 = (t + 1) * kPi / kPbrtThetaRes;
        for (int p = 0; p < kPbrtPhiRes; ++p) {
            const double p0 = p * 2 * kPi / kPbrtPhiRes, p1 = (p + 1) * 2 * kPi / kPbrtPhiRes;
            auto over_phi = [&](double theta) {
                const double st = std::sin(theta), ct = std::cos(theta);
                auto f = [&](double phi) { return pdf(st * std::cos(phi), st * std::sin(phi), ct) * st; };
                return adaptive_simpson(f, p0, p1, 1e-6, 6);
            };
            expected[static_cast<std::size_t>(t * kPbrtPhiRes + p)] =
                adaptive_simpson(over_phi, t0, t1, 1e-6, 6) * static_cast<double>(samples);
        }
    }
    // Pool cells below 5 expected, in order of expected count, into one.
    std::vector<std::size_t> order(observed.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });
    double pooled_obs = 0, pooled_exp = 0, chsq = 0;
    int dof = 0;
    for (std::size_t i : order) {
        if (expected[i] == 0) continue;
        if (expected[i] < 5) {
            pooled_obs += observed[i];
            pooled_exp += expected[i];
        } else {
            chsq += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
            ++dof;
        }
    }
    if (pooled_exp > 0) {
        chsq += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        ++dof;
    }
    return boost::math::cdf(boost::math::complement(boost::math::chi_squared(std::max(dof - 1, 1)), chsq));
}

}  // namespace warpcheck::bench
