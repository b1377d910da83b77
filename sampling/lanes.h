// Eight samples at once: the lane types of the vectorised chi-square path
// (validate/lanes/lane_sampling.h) and the lane forms of the helpers the warps use.
//
// The types are GCC vector extensions (also understood by Clang). Code written
// with them compiles to AVX-512 inside a function built for that target and to
// plain SSE2 or scalar code elsewhere, with the same IEEE operations in the same
// order, so both give the same bits: no library calls (but one: pow, below),
// no fused multiply-add (the project builds with -ffp-contract=off), no
// approximate reciprocals.
// Every helper is always_inline, so none is ever compiled for one target and
// called from another.
//
// Each lane form repeats its scalar twin operation for operation; the tests in
// tests/sampling/test_lanes.cpp compare them bit for bit.
#pragma once

#include <bit>
#include <cstdint>

#include "sampling/math.h"
#include "sampling/pcg32.h"

#ifdef __AVX512F__
#include <immintrin.h>
#endif

// GCC notes that passing 64-byte vectors changes the ABI without AVX-512; these
// functions are always inlined and never cross a translation unit.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace warpcheck::lanes {

inline constexpr int kWidth = 8;

using F32 = float __attribute__((vector_size(4 * kWidth)));
using I32 = int32_t __attribute__((vector_size(4 * kWidth)));
using U32 = uint32_t __attribute__((vector_size(4 * kWidth)));
using F64 = double __attribute__((vector_size(8 * kWidth)));
using I64 = int64_t __attribute__((vector_size(8 * kWidth)));
using U64 = uint64_t __attribute__((vector_size(8 * kWidth)));

#define WARPCHECK_LANE [[gnu::always_inline]] inline

/// a where the mask is set (all ones), b elsewhere.
template <typename Mask, typename V>
WARPCHECK_LANE V select(Mask m, V a, V b) {
    return m ? a : b;
}

WARPCHECK_LANE F64 to_f64(F32 x) { return __builtin_convertvector(x, F64); }
WARPCHECK_LANE F32 to_f32(F64 x) { return __builtin_convertvector(x, F32); }

/// |x| by clearing the sign bit, as std::abs does (-0 becomes +0).
WARPCHECK_LANE F32 abs(F32 x) { return std::bit_cast<F32>(std::bit_cast<U32>(x) & 0x7fffffffu); }
WARPCHECK_LANE F64 abs(F64 x) { return std::bit_cast<F64>(std::bit_cast<U64>(x) & 0x7fffffffffffffffull); }

/// IEEE square root per lane (one vsqrtps inside an AVX-512 function).
WARPCHECK_LANE F32 sqrt(F32 x) {
    F32 r;
    for (int i = 0; i < kWidth; ++i) r[i] = __builtin_sqrtf(x[i]);
    return r;
}

/// IEEE square root per lane, in double.
WARPCHECK_LANE F64 sqrt(F64 x) {
    F64 r;
    for (int i = 0; i < kWidth; ++i) r[i] = __builtin_sqrt(x[i]);
    return r;
}

/// std::max(x, 0.0f) as the standard defines it ((x < 0) ? 0 : x, so NaN and -0 pass through).
WARPCHECK_LANE F32 max_zero(F32 x) { return select(x < 0.0f, F32{} + 0.0f, x); }

/// safe_sqrt of sampling/math.h.
WARPCHECK_LANE F32 safe_sqrt(F32 x) { return sqrt(max_zero(x)); }

/// sin_from_cos of sampling/math.h.
WARPCHECK_LANE F32 sin_from_cos(F32 z) { return safe_sqrt((1.0f - z) * (1.0f + z)); }

/// std::pow(x, y) of each lane: libm's powf, called lane by lane. No
/// polynomial of ours could stand in for it: glibc's powf is not correctly
/// rounded (within 0.82 ulp), so only powf itself gives its bits. Both
/// builds call the one powf of the process, which the scalar warps call too
/// (std::pow of floats is __builtin_powf), so the bits are the scalar form's.
WARPCHECK_LANE F32 pow(F32 x, float y) {
    F32 r;
    for (int i = 0; i < kWidth; ++i) r[i] = __builtin_powf(x[i], y);
    return r;
}

// The same functions of one float, so that a warp written as a template over
// its float type (validate/api/float_template_warp.h) calls lanes::sqrt and
// friends for either.
WARPCHECK_LANE float abs(float x) { return std::abs(x); }
WARPCHECK_LANE float sqrt(float x) { return std::sqrt(x); }
WARPCHECK_LANE float max_zero(float x) { return x < 0.0f ? 0.0f : x; }
WARPCHECK_LANE float safe_sqrt(float x) { return warpcheck::safe_sqrt(x); }
WARPCHECK_LANE float sin_from_cos(float z) { return warpcheck::sin_from_cos(z); }
WARPCHECK_LANE float pow(float x, float y) { return std::pow(x, y); }

/// The operations of detail::sin_cos_core on lanes of doubles.
struct DoubleOps {
    using Real = F64;
    using Int = I64;
    WARPCHECK_LANE static Int truncate(Real x) { return __builtin_convertvector(x, Int); }
    WARPCHECK_LANE static Real to_real(Int k) { return __builtin_convertvector(k, Real); }
    WARPCHECK_LANE static Real select(Int m, Real a, Real b) { return m ? a : b; }
};

struct SinCos {
    F32 sin, cos;
};

struct SinCosDouble {
    F64 sin, cos;
};

/// warpcheck::sin_cos_double on lanes; every lane must hold |x| <= 10.
WARPCHECK_LANE SinCosDouble sin_cos_double(F64 x) {
    SinCosDouble r;
    detail::sin_cos_core<DoubleOps>(x, r.sin, r.cos);
    return r;
}

/// warpcheck::sin_cos on lanes. Every lane must hold |phi| <= 10 (the scalar
/// form defers to libm beyond; the lane form is only used where the warp's
/// angles lie in [-pi/4, 2 pi]).
WARPCHECK_LANE SinCos sin_cos(F32 phi) {
    F64 s, c;
    detail::sin_cos_core<DoubleOps>(to_f64(phi), s, c);
    return {to_f32(s), to_f32(c)};
}

/// warpcheck::sin_cos, for a template over the float type.
WARPCHECK_LANE warpcheck::SinCos sin_cos(float phi) { return warpcheck::sin_cos(phi); }

/// Eight (kWidth) PCG32 generators stepped together, lane l a copy of one Pcg32.
struct Pcg32Lanes {
    U64 state{}, inc{};

    /// One step of each lane's generator, done in its 64-bit lane: the output
    /// in the low 32 bits (and again in the high 32). No narrowing to 32-bit
    /// lanes and back, which costs shuffles: the xorshifted value, copied into
    /// both halves, is rotated as a 64-bit word, whose low half is then the
    /// 32-bit rotation (a single vprorvq on AVX-512).
    WARPCHECK_LANE U64 step() {
        const U64 old = state;
        state = old * Pcg32::kMultiplier + inc;
        // Pcg32's xorshifted output is the low 32 bits of this (37 bits wide:
        // the top 5 must not reach the high half, hence the mask below).
        const U64 xorshifted = ((old >> 18u) ^ old) >> 27u;
        const U64 doubled = (xorshifted << 32u) | (xorshifted & 0xffffffffu);
        const U64 rot = old >> 59u;
#ifdef __AVX512F__
        // GCC does not see the rotation in the shifts below on vectors. Both
        // branches give the same bits; the function is always inlined, so the
        // two definitions never meet (the ctest lane_objects_are_isolated
        // checks that the AVX-512 object defines nothing shared). (The
        // maskz form: the plain one starts from an undefined vector, which GCC
        // 12 warns about.)
        return std::bit_cast<U64>(
            _mm512_maskz_rorv_epi64(0xff, std::bit_cast<__m512i>(doubled), std::bit_cast<__m512i>(rot)));
#else
        return (doubled >> rot) | (doubled << ((64u - rot) & 63u));
#endif
    }
    WARPCHECK_LANE U32 next_u32() { return __builtin_convertvector(step() & 0xffffffffu, U32); }
    /// Pcg32::next_u64: the first draw is the high half.
    WARPCHECK_LANE U64 next_u64() {
        const U64 hi = step();
        return (hi << 32u) | (step() & 0xffffffffu);
    }
};

/// uniform_float_from_bits (validate/checks/check.h) on lanes: w * 2^-64 rounded down
/// to a float. The 24 leading bits of w are cut from the double nearest to w
/// (exact for w < 2^53) or to w >> 11 (exact for any w, and it keeps all of
/// w's leading 24 bits when w >= 2^53), by clearing the low 29 of the
/// double's 52 stored significand bits; then the power of two rescales.
WARPCHECK_LANE F32 uniform_float_from_bits(U64 w) {
    constexpr uint64_t kBig = uint64_t{1} << 53;
    const U64 part = w >= kBig ? w >> 11u : w;
    const F64 d = __builtin_convertvector(part, F64);
    const F64 cut = std::bit_cast<F64>(std::bit_cast<U64>(d) & ~((uint64_t{1} << 29) - 1));
    // 24 significant bits times a power of two >= 2^-64: exact in double and in float.
    return to_f32(cut * (w >= kBig ? F64{} + 0x1p-53 : F64{} + 0x1p-64));
}

}  // namespace warpcheck::lanes

#pragma GCC diagnostic pop
