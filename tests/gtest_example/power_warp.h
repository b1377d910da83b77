// A renderer's own warp: x in [0,1] with density (n+1) x^n (a power-law lobe).
#pragma once

#include <cmath>

struct PowerWarp {
    float n;
    /// The inverse of the CDF x^(n+1).
    float sample(float u) const { return std::pow(u, 1 / (n + 1)); }
    float pdf(float x) const { return x < 0 || x > 1 ? 0 : (n + 1) * std::pow(x, n); }
    /// The CDF, kept below 1: sample rounds its largest inputs up to x = 1, and
    /// an inverse must return a valid input u of [0,1).
    float invert(float x) const { return std::fmin(std::pow(x, n + 1), 0x1.fffffep-1f); }
};

/// A bug of the kind warpcheck is for: the exponent of n = 2 in sample, with
/// the density of n = 3 (copied from the next lobe).
struct WrongPowerWarp {
    float sample(float u) const { return PowerWarp{2}.sample(u); }
    float pdf(float x) const { return PowerWarp{3}.pdf(x); }
    float invert(float x) const { return PowerWarp{2}.invert(x); }
};
