// Constants and small numeric helpers shared by the warps.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sampling/float_bits.h"

namespace warpcheck {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kInvPi = std::numbers::inv_pi_v<float>;
inline constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
inline constexpr float kInvTwoPi = 0.5f * std::numbers::inv_pi_v<float>;
inline constexpr float kInvFourPi = 0.25f * std::numbers::inv_pi_v<float>;
inline constexpr float kPiOver2 = 0.5f * std::numbers::pi_v<float>;
inline constexpr float kPiOver4 = 0.25f * std::numbers::pi_v<float>;
inline constexpr float kFourOverPi = 4.0f * std::numbers::inv_pi_v<float>;

/// sqrt that maps the small negative results of rounding (and only those) to 0.
inline float safe_sqrt(float x) { return std::sqrt(std::max(x, 0.0f)); }

/// sqrt(1 - z^2) for |z| <= 1, computed as sqrt((1 - z)(1 + z)): accurate near
/// |z| = 1, where 1 - z*z loses the low bits of z.
inline float sin_from_cos(float z) { return safe_sqrt((1.0f - z) * (1.0f + z)); }

/// The azimuth of (x, y) as a fraction of a full turn, in [0, 1): the inverse of
/// phi = 2 pi u. Rounding can land exactly on 1 for phi just below 2 pi; that is
/// clamped to the largest float below 1 so the result stays a valid input.
inline float azimuth_to_unit(float x, float y) {
    float phi = std::atan2(y, x);
    if (phi < 0.0f) phi += kTwoPi;
    return std::min(phi * kInvTwoPi, kOneMinusEpsilon);
}

}  // namespace warpcheck
