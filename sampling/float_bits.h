// Bit-level view of IEEE-754 binary32 floats: the vocabulary of the float-level
// samplers and of the exhaustive histogram counts.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace warpcheck {

inline constexpr int kFloatSignificandBits = 23;
inline constexpr int kFloatExponentBias = 127;
inline constexpr uint32_t kFloatSignificandMask = (1u << kFloatSignificandBits) - 1;
inline constexpr uint32_t kFloatExponentMask = 0xffu << kFloatSignificandBits;
inline constexpr uint32_t kFloatSignMask = 0x80000000u;

/// The largest float below 1: 1 - 2^-24.
inline constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

constexpr uint32_t float_to_bits(float f) { return std::bit_cast<uint32_t>(f); }
constexpr float bits_to_float(uint32_t bits) { return std::bit_cast<float>(bits); }

/// 1 for negative floats (including -0 and negative NaNs), 0 otherwise.
constexpr uint32_t float_sign_bit(float f) { return float_to_bits(f) >> 31; }

/// The biased exponent field, 0..255 (0: zero and denormals, 255: inf and NaN).
constexpr int float_biased_exponent(float f) {
    return static_cast<int>((float_to_bits(f) & kFloatExponentMask) >> kFloatSignificandBits);
}

/// The unbiased exponent of a normal float (floor(log2|f|)); denormals report -127.
constexpr int float_exponent(float f) { return float_biased_exponent(f) - kFloatExponentBias; }

/// The 23 stored significand bits, without the implicit leading one.
constexpr uint32_t float_significand(float f) { return float_to_bits(f) & kFloatSignificandMask; }

/// The next float towards +infinity. +inf and NaN map to themselves; -0 steps to
/// the smallest positive denormal, as +0 does.
constexpr float next_float_up(float f) {
    if (f != f || f == std::numeric_limits<float>::infinity()) return f;
    if (f == 0.0f) return bits_to_float(1u);
    const uint32_t bits = float_to_bits(f);
    return bits_to_float(f > 0.0f ? bits + 1 : bits - 1);
}

/// The next float towards -infinity. -inf and NaN map to themselves.
constexpr float next_float_down(float f) {
    if (f != f || f == -std::numeric_limits<float>::infinity()) return f;
    if (f == 0.0f) return -bits_to_float(1u);
    const uint32_t bits = float_to_bits(f);
    return bits_to_float(f > 0.0f ? bits - 1 : bits + 1);
}

constexpr int count_leading_zeros(uint32_t v) { return std::countl_zero(v); }
constexpr int count_leading_zeros(uint64_t v) { return std::countl_zero(v); }

}  // namespace warpcheck
