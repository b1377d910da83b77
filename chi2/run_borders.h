// Run borders of consecutive outputs, 64 at a time in AVX-512 registers: the
// kernel of the exhaustive sweep's run scan (chi2/float_sweep.h). The sweep
// uses it on blocks of outputs in memory; a sampler inlined into a loop of its
// own uses it on outputs still in registers (validate/api/exhaustive_sweep.h), so
// that a monotone sweep never stores its outputs. Only for x86-64 with GCC or
// clang; elsewhere the sweep's portable scan is the only one.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

// The instruction sets of every function that calls the kernel.
#define WARPCHECK_BORDERS_TARGET "avx512f,avx512dq,avx512vl,avx512bw,popcnt"

namespace warpcheck::chi2::detail {

/// Whether this processor has every instruction set of WARPCHECK_BORDERS_TARGET
/// (AVX-512F alone is not enough: GCC may use BW mask instructions in the
/// kernel, which a Knights Landing lacks). Every caller of the kernel checks it.
inline bool borders_kernel_supported() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("popcnt");
}

/// Where borders go: position and output bits of each, count so far. Both
/// arrays need 16 entries of room past the last border.
struct BorderList {
    uint32_t* positions = nullptr;
    uint32_t* bits = nullptr;
    std::size_t count = 0;
};

/// Appends the borders among 32 consecutive outputs v0, v1 (position `at`
/// for v0's lane 0), where `previous` holds the bits of the output before
/// them in lane 15: each lane is compared with the one before it. One branch,
/// on whether there is at most one border (runs of 32 and more), which follows
/// the run length, not where the borders fall. With none, it appends nothing.
__attribute__((target(WARPCHECK_BORDERS_TARGET), always_inline)) inline void append_borders_32(
    __m512i v0, __m512i v1, __m512i previous, uint32_t at, BorderList& out) {
    // [previous[15], v0[0..14]] and [v0[15], v1[0..14]]. (The maskz forms: the
    // plain ones start from an undefined vector, which GCC 12 warns about.)
    const __mmask16 m0 = _mm512_cmpneq_epu32_mask(v0, _mm512_maskz_alignr_epi32(0xffff, v0, previous, 15));
    const __mmask16 m1 = _mm512_cmpneq_epu32_mask(v1, _mm512_maskz_alignr_epi32(0xffff, v1, v0, 15));
    const uint32_t mask = static_cast<uint32_t>(m0) | static_cast<uint32_t>(m1) << 16;
    if ((mask & (mask - 1)) == 0) {
        // One border, at lane j: every lane from j on holds its output, the
        // last one too (v1[15], which the caller broadcasts anyway). No border:
        // the entry written is not counted.
        out.positions[out.count] = at + static_cast<uint32_t>(std::countr_zero(mask));
        out.bits[out.count] = static_cast<uint32_t>(
            _mm512_cvtsi512_si32(_mm512_maskz_permutexvar_epi32(0xffff, _mm512_set1_epi32(15), v1)));
        out.count += mask != 0;
        return;
    }
    // Compress in a register and store all 16 lanes (the store form of
    // vpcompressd is slow on some cores), for both vectors, empty or not.
    const __m512i lanes = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512i index = _mm512_add_epi32(_mm512_set1_epi32(static_cast<int>(at)), lanes);
    _mm512_storeu_si512(out.positions + out.count, _mm512_maskz_compress_epi32(m0, index));
    _mm512_storeu_si512(out.bits + out.count, _mm512_maskz_compress_epi32(m0, v0));
    out.count += static_cast<std::size_t>(std::popcount(static_cast<unsigned>(m0)));
    const __m512i index1 = _mm512_add_epi32(index, _mm512_set1_epi32(16));
    _mm512_storeu_si512(out.positions + out.count, _mm512_maskz_compress_epi32(m1, index1));
    _mm512_storeu_si512(out.bits + out.count, _mm512_maskz_compress_epi32(m1, v1));
    out.count += static_cast<std::size_t>(std::popcount(static_cast<unsigned>(m1)));
}

/// Appends the borders among 64 consecutive outputs v0..v3 (position `at` for
/// v0's lane 0), where `previous` holds the bits of the output before them in
/// every lane. Most groups of 64 hold no border in a monotone sweep (runs are
/// hundreds long): that costs three bitwise operations and one mask test; a
/// group with a border is looked at in halves.
__attribute__((target(WARPCHECK_BORDERS_TARGET), always_inline)) inline void append_borders_64(
    __m512i v0, __m512i v1, __m512i v2, __m512i v3, __m512i previous, uint32_t at, BorderList& out) {
    const __m512i d01 = _mm512_ternarylogic_epi32(v0, v1, previous, 0x7e);  // (v0 ^ p) | (v1 ^ p)
    const __m512i d23 = _mm512_ternarylogic_epi32(v2, v3, previous, 0x7e);
    const __m512i any = _mm512_or_si512(d01, d23);
    if (_mm512_test_epi32_mask(any, any) == 0) return;
    if (_mm512_test_epi32_mask(d01, d01) != 0) {
        append_borders_32(v0, v1, previous, at, out);
        previous = _mm512_maskz_permutexvar_epi32(0xffff, _mm512_set1_epi32(15), v1);
    }
    const __m512i e23 = _mm512_ternarylogic_epi32(v2, v3, previous, 0x7e);
    if (_mm512_test_epi32_mask(e23, e23) != 0) append_borders_32(v2, v3, v1, at + 32, out);
}

/// The bits of lane 15 of v in every lane: the `previous` of the next 64.
__attribute__((target(WARPCHECK_BORDERS_TARGET), always_inline)) inline __m512i last_lane(__m512i v) {
    return _mm512_maskz_permutexvar_epi32(0xffff, _mm512_set1_epi32(15), v);
}

}  // namespace warpcheck::chi2::detail
#endif
