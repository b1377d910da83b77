// Floats in [0,1) from random bits: the five ways renderers do it, with their
// inverses, so that the exhaustive counts can say exactly how biased each is.
//
// Each method is a warp (sampling/README.md): `UnitFloat<Method>{}.sample(bits)`
// samples, `pdf(x)` is the density they all aim at (1 on [0,1)), and `invert(x)`
// returns the smallest input that the sampler maps to x, so for a monotone
// sampler it is the CDF on the input grid: P(sample < x) = invert(x) * 2^-k.
//
// The reference measure throughout is "uniform real, rounded down to a float":
// a float x of [0,1) should come out with probability next_float_up(x) - x, its
// spacing. 2^-32 inputs cannot give a 2^-149 spacing, so every 32-bit method is
// off somewhere; the exhaustive check (validate/checks/exhaustive/exhaustive_check.cpp) counts by how much.
#pragma once

#include <bit>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "sampling/float_bits.h"

namespace warpcheck {

namespace detail {

/// floor(w * 2^k) rounded down to a float (towards zero), for w * 2^k < 2^128.
/// Exact: truncates w to its 24 leading bits (or, below 2^-126, to the 2^-149
/// grid of the denormals) and scales by a power of two.
constexpr float scaled_u64_to_float_down(uint64_t w, int k) {
    if (w == 0) return 0.0f;
    const int msb = 63 - std::countl_zero(w);  // w in [2^msb, 2^(msb+1))
    const int e = msb + k;                     // value in [2^e, 2^(e+1))
    if (e >= -126) {
        const uint64_t sig = msb >= 23 ? w >> (msb - 23) : w << (23 - msb);  // 24 bits, leading 1
        return bits_to_float(static_cast<uint32_t>(e + kFloatExponentBias) << kFloatSignificandBits |
                             (static_cast<uint32_t>(sig) & kFloatSignificandMask));
    }
    // Denormal: count in units of 2^-149. The result is below 2^23 units.
    const int shift = k + 149;
    const uint64_t units = shift >= 0 ? w << shift : (-shift >= 64 ? 0 : w >> -shift);
    return bits_to_float(static_cast<uint32_t>(units));
}

/// The exact value x * 2^k as an integer, for a finite x >= 0 that is a multiple
/// of 2^-k (the caller guarantees it) and x * 2^k < 2^64.
constexpr uint64_t float_to_scaled_u64(float x, int k) {
    if (x == 0.0f) return 0;
    const uint32_t bits = float_to_bits(x);
    const int biased = static_cast<int>(bits >> kFloatSignificandBits);
    const uint64_t sig = biased == 0 ? (bits & kFloatSignificandMask)
                                     : ((bits & kFloatSignificandMask) | (1u << kFloatSignificandBits));
    const int exp2 = (biased == 0 ? 1 : biased) - kFloatExponentBias - kFloatSignificandBits + k;  // x = sig 2^exp2'
    return exp2 >= 0 ? sig << exp2 : sig >> -exp2;
}

/// 64 random bits from a callable returning uint64_t, or two calls of one that
/// returns uint32_t (the first call gives the high half).
template <typename Rng>
uint64_t draw_u64(Rng& rng) {
    using R = std::invoke_result_t<Rng&>;
    static_assert(std::is_same_v<R, uint64_t> || std::is_same_v<R, uint32_t>,
                  "a random source returns uint64_t or uint32_t");
    if constexpr (std::is_same_v<R, uint64_t>) {
        return rng();
    } else {
        const uint64_t hi = rng();
        return hi << 32 | rng();
    }
}

/// A float of [0, 2^(top+1)) with the exact measure of a uniform real rounded
/// down, i.e. P(x) = (next_float_up(x) - x) / 2^(top+1), down to the denormals.
/// `w` holds the first `word_bits` random bits (w < 2^word_bits) and is read as
/// the leading bits of the real: for w >= 2^23 the result is floor(w 2^(top+1-
/// word_bits)) and so is monotone in w. Below that (probability 2^(23-word_bits))
/// w becomes the significand and the exponent continues Walker's count of
/// leading zeros over fresh words from `rng`; at most 5 more words are drawn.
/// Requires -127 <= top <= 127 (top = -127: the denormals alone).
template <typename Rng>
float sample_below_power_of_two(int top, uint64_t w, int word_bits, Rng& rng) {
    const int first_region_exponent = top + 24 - word_bits;  // w < 2^23 <=> value < 2^this
    if (w >= (uint64_t{1} << 23) || first_region_exponent <= -126)
        return scaled_u64_to_float_down(w, top + 1 - word_bits);
    // The real lies in [0, 2^(first_region_exponent)), below `zeros` leading zeros.
    int zeros = word_bits - 23;
    const int denormal_zeros = top + 127;  // top - zeros < -126: the denormal binade
    for (int draws = 0; draws < 6 && zeros < denormal_zeros; ++draws) {
        const uint64_t v = draw_u64(rng);
        if (v != 0) {
            zeros += std::countl_zero(v);
            break;
        }
        zeros += 64;
    }
    const uint32_t significand = static_cast<uint32_t>(w);  // 23 uniform bits
    if (zeros >= denormal_zeros) return bits_to_float(significand);
    return bits_to_float(static_cast<uint32_t>(top - zeros + kFloatExponentBias) << kFloatSignificandBits |
                         significand);
}

/// The smallest first word w (of `word_bits` bits) for which
/// sample_below_power_of_two(top, w, word_bits, .) returns m, for m >= 2^(top +
/// 24 - word_bits) (the part reached from the first word alone).
constexpr uint64_t below_power_of_two_first_word(int top, float m, int word_bits) {
    return float_to_scaled_u64(m, word_bits - 1 - top);
}

}  // namespace detail

/// The density every sampler of [0,1) aims at: 1 on [0,1), 0 elsewhere (the
/// exhaustive counts, not the density, measure how far each falls short).
struct UnitIntervalDensity {
    constexpr float pdf(float x) const { return x >= 0.0f && x < 1.0f ? 1.0f : 0.0f; }
};

// ---------------------------------------------------------------------------
// [0,1) from 32 bits

/// u * 2^-32 in float.
struct UnitFloatMul : UnitIntervalDensity {
    /// u * 2^-32 in float, rounded to nearest even: the most common way and the most
    /// biased. Returns 1.0 for the 128 largest u (it leaves [0,1)); below 2^-8 only
    /// some floats are reachable; in [0.5, 1) floats come 257 and 255 times
    /// alternately (ties go to the even significand) instead of 256.
    constexpr float sample(uint32_t u) const { return static_cast<float>(u) * 0x1p-32f; }

    /// The smallest u with UnitFloatMul{}.sample(u) >= x (x in [0,1]; 0 for x <= 0,
    /// UINT32_MAX above 1): for a float that is produced, its first preimage.
    constexpr uint32_t invert(float x) const {
        if (!(x > 0.0f)) return 0;
        if (x > 1.0f) return std::numeric_limits<uint32_t>::max();
        // Reals in (midpoint below x, midpoint above x) round to x; the midpoint
        // itself goes to the even neighbour. In double, the midpoint times 2^32 is
        // exact; start at its ceiling and correct the tie by at most one step.
        const double mid = (static_cast<double>(next_float_down(x)) + static_cast<double>(x)) * 0x1p31;
        double c = mid;
        if (c != static_cast<double>(static_cast<uint64_t>(c))) c = static_cast<double>(static_cast<uint64_t>(c) + 1);
        uint64_t u = static_cast<uint64_t>(c);
        if (u > 0 && sample(static_cast<uint32_t>(u - 1)) >= x) --u;
        while (u < 0xffffffffu && sample(static_cast<uint32_t>(u)) < x) ++u;
        return static_cast<uint32_t>(u > 0xffffffffu ? 0xffffffffu : u);
    }
};

/// u * 2^-32 in float, clamped below 1.
struct UnitFloatMulClamped : UnitIntervalDensity {
    /// u * 2^-32 clamped to the largest float below 1, as many renderers patch the
    /// above. It stays in [0,1), but 0x1.fffffep-1 now takes the 128 inputs that
    /// rounded to 1 on top of its own 255: 383 instead of 256.
    constexpr float sample(uint32_t u) const {
        const float x = UnitFloatMul{}.sample(u);
        return x < kOneMinusEpsilon ? x : kOneMinusEpsilon;
    }

    /// First preimage of x under UnitFloatMulClamped::sample (x in [0,1)): the
    /// clamp only adds inputs above the old ones, so it is that of the plain multiply.
    constexpr uint32_t invert(float x) const { return UnitFloatMul{}.invert(x); }
};

/// The top 24 of 32 bits on the 2^-24 grid.
struct UnitFloat24Bit : UnitIntervalDensity {
    /// (u >> 8) * 2^-24: the top 24 bits on the 2^-24 grid. Exact, never 1, and
    /// every value comes exactly 256 times, but only 2^24 of the 2^30 floats of
    /// [0,1) are reachable (the grid is coarse near 0).
    constexpr float sample(uint32_t u) const { return static_cast<float>(u >> 8) * 0x1p-24f; }

    /// The smallest u with UnitFloat24Bit{}.sample(u) >= x, for x in [0,1).
    constexpr uint32_t invert(float x) const {
        if (!(x > 0.0f)) return 0;
        const double scaled = static_cast<double>(x) * 0x1p24;  // exact
        const auto k = static_cast<uint64_t>(scaled);
        const uint64_t grid = k + (static_cast<double>(k) < scaled ? 1 : 0);
        return grid >= (uint64_t{1} << 24) ? std::numeric_limits<uint32_t>::max() : static_cast<uint32_t>(grid << 8);
    }
};

/// 23 bits as the significand of [1,2), minus 1.
struct UnitFloatBits : UnitIntervalDensity {
    /// The bit trick: 23 random bits as the significand of a float in [1,2), minus
    /// 1. The subtraction is exact, so this is the 2^-23 grid: 2^23 values, each
    /// 512 times; the finest spacing is 2^-23 even next to 0.
    constexpr float sample(uint32_t u) const {
        return bits_to_float(0x3f800000u | (u >> 9)) - 1.0f;  // 0x3f800000 is 1.0f
    }

    /// The smallest u with UnitFloatBits{}.sample(u) >= x, for x in [0,1).
    constexpr uint32_t invert(float x) const {
        if (!(x > 0.0f)) return 0;
        const double scaled = static_cast<double>(x) * 0x1p23;
        const auto k = static_cast<uint64_t>(scaled);
        const uint64_t grid = k + (static_cast<double>(k) < scaled ? 1 : 0);
        return grid >= (uint64_t{1} << 23) ? std::numeric_limits<uint32_t>::max() : static_cast<uint32_t>(grid << 9);
    }
};

// ---------------------------------------------------------------------------
// [0,1) from 64 bits

/// Reynolds' one-word sampler of every float of [0,1) above 2^-41.
struct UnitFloatReynolds : UnitIntervalDensity {
    /// Reynolds' pragmatic version: the leading zeros of the top 41 bits choose
    /// the binade (k zeros: [2^-(k+1), 2^-k), probability 2^-(k+1), as its width),
    /// the low 23 bits the significand. Every float >= 2^-41 has exactly its
    /// measure; below, if the top 41 bits are all zero (probability 2^-41), the
    /// result is bits * 2^-64, uniform on [0, 2^-41) on the 2^-64 grid. Never 1.
    /// One word, no loop, no branch on the fast path beyond the zero test.
    constexpr float sample(uint64_t bits) const {
        const uint64_t exponent_bits = bits >> 23;  // 41 bits
        const auto significand = static_cast<uint32_t>(bits) & kFloatSignificandMask;
        if (exponent_bits == 0) return static_cast<float>(significand) * 0x1p-64f;  // exact: < 2^23
        const int zeros = std::countl_zero(exponent_bits) - 23;                     // 0..40
        return bits_to_float(static_cast<uint32_t>(kFloatExponentBias - 1 - zeros) << kFloatSignificandBits |
                             significand);
    }

    /// The smallest 64-bit input with UnitFloatReynolds{}.sample(bits) == x, for a
    /// float x in [0,1) (below 2^-41: for x on the 2^-64 grid).
    constexpr uint64_t invert(float x) const {
        if (!(x > 0.0f)) return 0;
        if (x < 0x1p-41f) return detail::float_to_scaled_u64(x, 64);
        const int zeros = -1 - float_exponent(x);  // 0..40
        return (uint64_t{1} << (40 - zeros)) << 23 | float_significand(x);
    }
};

/// Walker's sampler of every float of [0,1), denormals included.
struct UnitFloatWalker : UnitIntervalDensity {
    /// Walker's algorithm: the exponent from the count of leading zeros of as many
    /// random words as needed (k zeros: binade [2^-(k+1), 2^-k)), down to the
    /// denormals, and 23 uniform significand bits. Each float of [0,1) has exactly
    /// its measure, next_float_up(x) - x, including every denormal and 0 (2^-149).
    /// `rng` is any callable returning uint64_t (or uint32_t, called twice).
    ///
    /// The significand is read from the bits right after the first one of the
    /// first word, so that with probability 1 - 2^-41 the result is
    /// floor(w * 2^-64) rounded down to a float: monotone in the first word w, with
    /// the first preimage given by UnitFloatWalker::invert. Otherwise (w < 2^23)
    /// w is the significand and up to 5 more words continue the count; the loop
    /// is bounded because below 2^-126 the denormals are uniform.
    template <typename Rng>
    float sample(Rng& rng) const {
        return detail::sample_below_power_of_two(-1, detail::draw_u64(rng), 64, rng);
    }

    /// The smallest first word with which UnitFloatWalker::sample returns x, for x in
    /// [2^-41, 1) (where one word decides). Below 2^-41 the further words decide too;
    /// this then returns the first word of that branch (x's significand).
    constexpr uint64_t invert(float x) const {
        if (!(x > 0.0f)) return 0;
        if (x < 0x1p-41f) return float_significand(x);
        return detail::below_power_of_two_first_word(-1, x, 64);
    }
};

}  // namespace warpcheck
