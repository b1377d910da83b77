// Exponential distributions: free-flight distances in a homogeneous medium,
// decaying lobes, and their trimmed versions on a bounded segment. Inputs u in [0,1).
//
// The textbook forms -log(1 - u)/a and (1 - exp(-c x))/(1 - exp(-c xmax)) lose
// everything near u = 0 and near c xmax = 0: 1 - u rounds to 1 for every float u
// below 2^-25 (so -log(1 - u) returns 0 for about 80% of all floats in [0,1)),
// and 1 - exp(-c xmax) cancels to 0 for a small rate. Here every formula is
// written with log1p and expm1 and the ratios
//     exprel(y)   = expm1(y) / y    (-> 1 as y -> 0)
//     log1prel(y) = log1p(y) / y    (-> 1 as y -> 0)
// which are well conditioned everywhere they are used, so the rate may go to 0
// (the trimmed exponential becomes uniform) and u may be as small as a denormal.
//
// Measured accuracy of sample(u) against a long double reference, in float ulps
// of the result (denormal results: in units of 2^-149); tests/sampling/
// test_exponential.cpp, *AccuracyNearZero, WARPCHECK_FULL_SWEEP=1 for every float:
//   Exponential, every float u in [0, 2^-20] (897,581,056 inputs) and in [2^-20, 1):
//     a = 0.1: 1.12 / 1.31 ulp;  a = 1: 0.50 / 0.83 ulp;  a = 10: 1.20 / 1.52 ulp.
//     (-log(1 - u)/a returns 0 for every u below 2^-25: 80% of the floats in [0,1).)
//   TrimmedExponential (x_max = 1), every float u in [0, 2^-20] and in [2^-20, 1):
//     c = 1e-6: 0.86 / 2.37 ulp;  c = 1: 1.93 / 3.44 ulp;  c = 100: 2.28 / 3.03 ulp;
//     c = 1e-30: exact (the product reduces to u x_max).
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sampling/float_bits.h"

namespace warpcheck {

namespace detail {

/// expm1(y) / y, with its limit 1 at y = 0. Accurate to a few ulps for every
/// finite y: expm1 and the division each round once, and there is no cancellation.
inline float exprel(float y) { return y == 0.0f ? 1.0f : std::expm1(y) / y; }

/// log1p(y) / y for y > -1, with its limit 1 at y = 0. Accurate to a few ulps.
inline float log1prel(float y) { return y == 0.0f ? 1.0f : std::log1p(y) / y; }

}  // namespace detail

/// The exponential distribution on [0, inf) with rate a > 0: p(x) = a exp(-a x),
/// CDF F(x) = 1 - exp(-a x). Densities are with respect to length.
class Exponential {
public:
    /// Smallest accepted rate: the largest sample, -log(2^-24)/a = 16.64/a, must be
    /// a finite float.
    static constexpr float kMinRate = 1e-37f;

    explicit Exponential(float rate) : a_(rate) {
        if (!(rate >= kMinRate) || !std::isfinite(rate))
            throw std::invalid_argument("exponential: rate must be finite and >= 1e-37, got " + std::to_string(rate));
    }

    float rate() const { return a_; }

    /// x = F^-1(u) = -log1p(-u) / a. log1p(-u) keeps full relative precision for
    /// tiny u, where -log(1 - u) would return 0. Inputs u >= 1 are treated as the
    /// largest float below 1, so every sample is finite.
    float sample(float u) const { return -std::log1p(-std::min(u, kOneMinusEpsilon)) / a_; }

    /// Density with respect to length: a exp(-a x) for x >= 0, else 0.
    float pdf(float x) const { return x >= 0.0f ? a_ * std::exp(-a_ * x) : 0.0f; }

    /// u = F(x) = -expm1(-a x), clamped to [0, 1 - 2^-24] so that it is a valid input.
    float invert(float x) const { return std::clamp(-std::expm1(-a_ * x), 0.0f, kOneMinusEpsilon); }

private:
    float a_;
};

/// The exponential distribution with rate c >= 0 trimmed to [0, xmax]:
///     p(x) = c exp(-c x) / (1 - exp(-c xmax)),   F(x) = expm1(-c x) / expm1(-c xmax).
/// With t = c xmax both are written through exprel, which removes the division
/// by a vanishing 1 - exp(-t) for small t: p(x) = exp(-c x) / (xmax exprel(-t)),
/// and c = 0 is the uniform distribution on [0, xmax] exactly. Densities are with
/// respect to length.
class TrimmedExponential {
public:
    TrimmedExponential(float rate, float x_max) : c_(rate), x_max_(x_max), t_(rate * x_max) {
        if (!(rate >= 0.0f) || !std::isfinite(rate))
            throw std::invalid_argument("trimmed_exponential: rate must be finite and >= 0, got " +
                                        std::to_string(rate));
        if (!(x_max > 0.0f) || !std::isfinite(x_max))
            throw std::invalid_argument("trimmed_exponential: x_max must be finite and > 0, got " +
                                        std::to_string(x_max));
        if (!std::isfinite(t_))
            throw std::invalid_argument("trimmed_exponential: rate * x_max overflows");
        expm1_neg_t_ = std::expm1(-t_);
        exprel_neg_t_ = detail::exprel(-t_);
        norm_ = 1.0f / (x_max_ * exprel_neg_t_);  // 1 / integral of exp(-c x) over [0, xmax]
        if (!std::isfinite(norm_))
            throw std::invalid_argument("trimmed_exponential: x_max too small, the density overflows");
    }

    float rate() const { return c_; }
    float x_max() const { return x_max_; }

    /// x = F^-1(u) = -log1p(u expm1(-t)) / c. Writing log1p(y) = y log1prel(y) and
    /// expm1(-t) = -t exprel(-t) cancels the division by c:
    ///     x = u xmax exprel(-t) log1prel(u expm1(-t)),
    /// a product of well-conditioned factors, exact for c = 0 (x = u xmax).
    float sample(float u) const {
        u = std::min(u, kOneMinusEpsilon);
        const float x = u * x_max_ * exprel_neg_t_ * detail::log1prel(u * expm1_neg_t_);
        return std::min(x, x_max_);  // the product may round a hair above xmax for u near 1
    }

    /// Density with respect to length: exp(-c x) / (xmax exprel(-t)) on [0, xmax], else 0.
    float pdf(float x) const { return x >= 0.0f && x <= x_max_ ? norm_ * std::exp(-c_ * x) : 0.0f; }

    /// u = F(x) = (x / xmax) exprel(-c x) / exprel(-t), clamped to [0, 1 - 2^-24].
    float invert(float x) const {
        x = std::clamp(x, 0.0f, x_max_);
        const float u = (x / x_max_) * (detail::exprel(-c_ * x) / exprel_neg_t_);
        return std::clamp(u, 0.0f, kOneMinusEpsilon);
    }

private:
    float c_;
    float x_max_;
    float t_;             // c xmax
    float expm1_neg_t_;   // expm1(-t), in [-1, 0]
    float exprel_neg_t_;  // exprel(-t), in (0, 1]
    float norm_;
};

}  // namespace warpcheck
