// The warp side of the exhaustive float sweep (the counting is
// chi2/float_sweep.h): the interface of cases that can be swept fast, and the
// vectorised block loop that turns a sampler into a chi2::FloatBlockFn.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>

#include "chi2/float_sweep.h"
#include "chi2/run_borders.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

// The counting lives in chi2; its names are used here unqualified, as before.
using chi2::BinadeCount;
using chi2::exhaustive_sweep;
using chi2::FloatBlockFn;
using chi2::FloatBordersFn;
using chi2::OutsideValue;
using chi2::ParallelFor;
using chi2::SweepSummary;

/// Implemented (besides WarpCase) by warp cases that the exhaustive check can
/// sweep fast: their sampler on the i-th input of its full input grid, in blocks.
class SweepableCase {
public:
    virtual ~SweepableCase() = default;
    /// out[i] = sample(input number first + i) of the grid.
    virtual FloatBlockFn sweep_fn() const = 0;
    /// sweep_fn fused with the sweep's run scan, or empty (chi2::FloatBordersFn).
    virtual FloatBordersFn sweep_borders_fn() const { return {}; }
    /// Size of the grid: 2^32 for 32-bit inputs, 2^24 for t = k 2^-24.
    virtual uint64_t sweep_inputs() const = 0;
    /// One line: which inputs, e.g. "all 2^32 inputs" or "t = k 2^-24, k < 2^24".
    virtual std::string sweep_grid() const = 0;
    /// Whether the sampler is meant to be monotone in its input: then a
    /// decreasing step is a failure, not just a figure.
    virtual bool claims_monotone() const = 0;
};

/// A warp case that also offers its sampler to the exhaustive sweep: it forwards
/// sample/pdf/invert to an ordinary case and adds the block function. Built by
/// the interval cases and by make_u32_float_case / make_u64_float_case
/// (validate/api/external.h).
class SweepableWarpCase final : public WarpCase, public SweepableCase {
public:
    SweepableWarpCase(std::unique_ptr<WarpCase> inner, FloatBlockFn fn, uint64_t inputs, std::string grid,
                      bool monotone, FloatBordersFn borders = {})
        : WarpCase(inner->info(), inner->signature()), inner_(std::move(inner)), fn_(std::move(fn)),
          borders_(std::move(borders)), inputs_(inputs), grid_(std::move(grid)), monotone_(monotone) {}

    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override { inner_->sample(in, out); }
    void sample_planar(const float* u0, const float* u1, float* x, float* y, float* z, std::size_t n) const override {
        inner_->sample_planar(u0, u1, x, y, z, n);
    }
    void sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                           std::span<double> value) const override {
        inner_->sample_with_value(in, out, value);
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override { inner_->pdf(x, out); }
    void eval(std::span<const WarpOutput> x, std::span<double> out) const override { inner_->eval(x, out); }
    void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const override { inner_->invert(x, out); }

    FloatBlockFn sweep_fn() const override { return fn_; }
    FloatBordersFn sweep_borders_fn() const override { return borders_; }
    uint64_t sweep_inputs() const override { return inputs_; }
    std::string sweep_grid() const override { return grid_; }
    bool claims_monotone() const override { return monotone_; }

private:
    std::unique_ptr<WarpCase> inner_;
    FloatBlockFn fn_;
    FloatBordersFn borders_;
    uint64_t inputs_;
    std::string grid_;
    bool monotone_;
};

namespace detail {

// The block loop, compiled for AVX-512, AVX2 or the baseline and chosen at run
// time. The sampler is inlined into each; IEEE operations give the same results
// on every instruction set (no FMA is enabled, so nothing is contracted). The
// x86 versions exist only where the compiler knows x86 targets; elsewhere the
// baseline loop is the only one.
#if defined(__x86_64__) && defined(__GNUC__)
template <typename F>
__attribute__((target("avx512f,avx512dq,avx512vl,avx512bw"))) void u32_block_avx512(const F& f, uint64_t first,
                                                                                      std::size_t n, float* out) {
    const auto base = static_cast<uint32_t>(first);
    const auto count = static_cast<uint32_t>(n);  // a 32-bit counter keeps the vector loop in 32-bit lanes
    for (uint32_t i = 0; i < count; ++i) out[i] = f(base + i);
}
template <typename F>
__attribute__((target("avx2"))) void u32_block_avx2(const F& f, uint64_t first, std::size_t n, float* out) {
    const auto base = static_cast<uint32_t>(first);
    const auto count = static_cast<uint32_t>(n);  // a 32-bit counter keeps the vector loop in 32-bit lanes
    for (uint32_t i = 0; i < count; ++i) out[i] = f(base + i);
}
#endif
// The sampler fused with the run scan (chi2::FloatBordersFn): 64 outputs at a
// time go from the sampler's vector loop to the border kernel
// (chi2/run_borders.h) through a 64-float array, instead of through a block in
// memory read back by a second loop. GCC 12 keeps that array in four
// registers (seen in the disassembly for u * 2^-32: no store in the loop);
// another compiler may store it, and then it stays in L1.
#if defined(__x86_64__) && defined(__GNUC__)
template <typename F>
__attribute__((target(WARPCHECK_BORDERS_TARGET))) std::size_t u32_borders_avx512(const F& f, uint64_t first,
                                                                                   std::size_t n, uint32_t previous,
                                                                                   uint32_t base, uint32_t* positions,
                                                                                   uint32_t* bits, uint32_t& last) {
    chi2::detail::BorderList out{positions, bits};
    const auto u = static_cast<uint32_t>(first);
    const auto count = static_cast<uint32_t>(n);
    alignas(64) float v[64];  // in registers with GCC 12 (see above)
    __m512i before = _mm512_set1_epi32(static_cast<int>(previous));
    const auto scan = [&](uint32_t i) __attribute__((target(WARPCHECK_BORDERS_TARGET))) {
        const __m512i v0 = _mm512_load_si512(v), v1 = _mm512_load_si512(v + 16);
        const __m512i v2 = _mm512_load_si512(v + 32), v3 = _mm512_load_si512(v + 48);
        chi2::detail::append_borders_64(v0, v1, v2, v3, before, base + i, out);
        before = chi2::detail::last_lane(v3);
    };
    uint32_t i = 0;
    // The inputs u + i + k, advanced by 64 a step: four vector additions, where
    // f(u + i + k) had GCC broadcast u + i and add four constants each step
    // (2^32 sweep of u * 2^-32 on one core: 377 -> 356 ms; on two 199 -> 172).
    alignas(64) uint32_t input[64];
    for (uint32_t k = 0; k < 64; ++k) input[k] = u + k;
    for (; count - i >= 64; i += 64) {
        for (uint32_t k = 0; k < 64; ++k) v[k] = f(input[k]);
        for (uint32_t k = 0; k < 64; ++k) input[k] += 64;
        scan(i);
    }
    if (i < count) {
        // The rest, padded with its last output (no borders in the padding).
        const uint32_t rest = count - i;
        for (uint32_t k = 0; k < 64; ++k) v[k] = f(u + i + (k < rest ? k : rest - 1));
        scan(i);
    }
    last = static_cast<uint32_t>(_mm512_cvtsi512_si32(before));
    return out.count;
}
#endif
template <typename F>
void u32_block_baseline(const F& f, uint64_t first, std::size_t n, float* out) {
    const auto base = static_cast<uint32_t>(first);
    const auto count = static_cast<uint32_t>(n);  // a 32-bit counter keeps the vector loop in 32-bit lanes
    for (uint32_t i = 0; i < count; ++i) out[i] = f(base + i);
}

}  // namespace detail

/// A FloatBlockFn evaluating `f(uint32_t) -> float` on consecutive inputs,
/// vectorised for the best instruction set of this CPU.
template <typename F>
FloatBlockFn u32_block_fn(F f) {
#if defined(__x86_64__) && defined(__GNUC__)
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw"))
        return [f](uint64_t first, std::size_t n, float* out) { detail::u32_block_avx512(f, first, n, out); };
    if (__builtin_cpu_supports("avx2"))
        return [f](uint64_t first, std::size_t n, float* out) { detail::u32_block_avx2(f, first, n, out); };
#endif
    return [f](uint64_t first, std::size_t n, float* out) { detail::u32_block_baseline(f, first, n, out); };
}

/// The FloatBordersFn of `f(uint32_t) -> float` (see u32_block_fn): fused
/// with the run scan where the CPU has AVX-512, empty elsewhere (the sweep
/// then scans the blocks of u32_block_fn).
template <typename F>
FloatBordersFn u32_borders_fn(F f) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (chi2::detail::borders_kernel_supported())
        return [f](uint64_t first, std::size_t n, uint32_t previous, uint32_t base, uint32_t* positions,
                   uint32_t* bits, uint32_t& last) {
            return detail::u32_borders_avx512(f, first, n, previous, base, positions, bits, last);
        };
#endif
    (void)f;
    return {};
}

/// A FloatBlockFn evaluating a 64-bit sampler `f(uint64_t) -> float` on the
/// inputs (i << shift) | low_bits, i consecutive (32 <= shift < 64): the high
/// bits swept, the low bits fixed.
template <typename F>
FloatBlockFn u64_block_fn(F f, int shift, uint64_t low_bits) {
    return [f, shift, low_bits](uint64_t first, std::size_t n, float* out) {
        for (std::size_t i = 0; i < n; ++i) out[i] = f(((first + i) << shift) | low_bits);
    };
}

}  // namespace warpcheck
