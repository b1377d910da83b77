// The reference of the chi-square benchmark: the procedure pbrt-v4's
// src/pbrt/bsdfs_test.cpp runs for its BSDFs, rebuilt here from its published
// description (no pbrt code), computing as it does: in float, with libm's
// float functions (acosf, atan2f, sinf, cosf, through std:: on floats).
//   - 80 x 160 (theta, phi) cells; a sample's cell from acos(clamped z) and
//     atan2(y, x) scaled by res / pi and res / (2 pi), floored and clamped;
//     counts kept in a float table; inputs u32 * 2^-32 clamped below 1.
//   - expected counts: sample count times the pdf times sin(theta) integrated
//     over each cell by nested adaptive Simpson in float, theta inside, phi
//     outside (tolerance 1e-6 halved per level, depth 6, Richardson's
//     correction), the integrand behind a std::function and computing cos and
//     sin of both angles at every evaluation;
//   - cells below 5 expected pooled in order of expected count until the pool
//     reaches 5, Pearson's statistic in float, dof = cells - 1, and the
//     p-value (here Boost's chi-squared complement; pbrt's own incomplete
//     gamma costs the same, once per test).
// Single-threaded, one sample at a time.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>

namespace warpcheck::bench {

constexpr int kPbrtThetaRes = 80, kPbrtPhiRes = 160;
constexpr float kPbrtPi = std::numbers::pi_v<float>;

/// A renderer's float cosine hemisphere as pbrt writes it: the concentric disk
/// with std::cos/std::sin on floats (libm cosf/sinf), lifted to the hemisphere.
inline std::array<float, 3> float_cosine_hemisphere(float u0, float u1) {
    const float a = 2 * u0 - 1, b = 2 * u1 - 1;
    float x = 0, y = 0;
    if (a != 0 || b != 0) {
        const bool wide = std::abs(a) > std::abs(b);
        const float r = wide ? a : b;
        const float theta = wide ? kPbrtPi / 4 * (b / a) : kPbrtPi / 2 - kPbrtPi / 4 * (a / b);
        x = r * std::cos(theta), y = r * std::sin(theta);
    }
    return {x, y, std::sqrt(std::max(0.0f, 1 - x * x - y * y))};
}

/// Adaptive Simpson in float on [x0, x1], tolerance eps halved per level, at most `depth` levels.
inline float float_adaptive_simpson(const std::function<float(float)>& f, float x0, float x1, float eps, int depth) {
    const std::function<float(float, float, float, float, float, float, float, float, int)> level =
        [&](float a, float b, float c, float fa, float fb, float fc, float whole, float tol, int d) -> float {
        const float l = 0.5f * (a + b), r = 0.5f * (b + c), fl = f(l), fr = f(r);
        const float h = c - a;
        const float left = h / 12 * (fa + 4 * fl + fb), right = h / 12 * (fb + 4 * fr + fc), both = left + right;
        if (d <= 0 || std::abs(both - whole) < 15 * tol) return both + (both - whole) / 15;
        return level(a, l, b, fa, fl, fb, left, 0.5f * tol, d - 1) + level(b, r, c, fb, fr, fc, right, 0.5f * tol, d - 1);
    };
    const float m = 0.5f * (x0 + x1), f0 = f(x0), fm = f(m), f1 = f(x1);
    return level(x0, m, x1, f0, fm, f1, (x1 - x0) / 6 * (f0 + 4 * fm + f1), eps, depth);
}

/// The p-value of `samples` draws of `sample(u0, u1) -> {x, y, z}` against
/// `pdf(x, y, z)` (floats, per solid angle).
template <typename Rng, typename Sample, typename Pdf>
double pbrt_style_chi2(Rng& rng, uint64_t samples, const Sample& sample, const Pdf& pdf) {
    const auto uniform = [&rng] { return std::min(0x1.fffffep-1f, static_cast<float>(rng.next_u32()) * 0x1p-32f); };
    std::vector<float> observed(kPbrtThetaRes * kPbrtPhiRes, 0.0f), expected(observed.size());
    const float theta_scale = kPbrtThetaRes / kPbrtPi, phi_scale = kPbrtPhiRes / (2 * kPbrtPi);
    for (uint64_t i = 0; i < samples; ++i) {
        const float u0 = uniform(), u1 = uniform();
        const auto [x, y, z] = sample(u0, u1);
        const float t = std::acos(std::clamp(z, -1.0f, 1.0f)) * theta_scale;
        float p = std::atan2(y, x) * phi_scale;
        if (p < 0) p += 2 * kPbrtPi * phi_scale;
        const int ti = std::clamp(static_cast<int>(std::floor(t)), 0, kPbrtThetaRes - 1);
        const int pc = std::clamp(static_cast<int>(std::floor(p)), 0, kPbrtPhiRes - 1);
        observed[static_cast<std::size_t>(ti * kPbrtPhiRes + pc)] += 1;
    }
    const float dt = kPbrtPi / kPbrtThetaRes, dp = 2 * kPbrtPi / kPbrtPhiRes;
    const std::function<float(float, float)> integrand = [&](float theta, float phi) {
        const float ct = std::cos(theta), st = std::sin(theta), cp = std::cos(phi), sp = std::sin(phi);
        return static_cast<float>(pdf(st * cp, st * sp, ct)) * st;
    };
    for (int t = 0; t < kPbrtThetaRes; ++t)
        for (int p = 0; p < kPbrtPhiRes; ++p) {
            const std::function<float(float)> over_theta = [&](float phi) {
                return float_adaptive_simpson([&](float theta) { return integrand(theta, phi); }, t * dt, (t + 1) * dt,
                                              1e-6f, 6);
            };
            expected[static_cast<std::size_t>(t * kPbrtPhiRes + p)] =
                static_cast<float>(samples) * float_adaptive_simpson(over_theta, p * dp, (p + 1) * dp, 1e-6f, 6);
        }
    // Pool cells below 5 expected, in order of expected count, until the pool reaches 5.
    std::vector<std::size_t> order(observed.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });
    float pooled_obs = 0, pooled_exp = 0, chsq = 0;
    int dof = 0;
    for (std::size_t i : order) {
        if (expected[i] == 0) continue;
        if (expected[i] < 5 || (pooled_exp > 0 && pooled_exp < 5)) {
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
