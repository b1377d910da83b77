// The lockstep loop of the vectorised chi-square path, instantiated once per
// built-in lane form in two translation units: lane_sampling.cpp (portable,
// the baseline target) and lane_sampling_avx512.cpp (the whole file built for
// x86-64-v4). The lane helpers must be compiled for the target they run on:
// inlined from a baseline build they arrive already split into 128-bit pieces.
// Everything here is always_inline and nothing calls out of it (no library
// call, no std::vector), so the AVX-512 file emits no shared inline function
// that the linker could pick for a caller on another processor; the ctest
// lane_avx512_object_is_isolated checks that.
#pragma once

#include <cstdint>
#include <cstring>
#ifdef __AVX512DQ__
#include <immintrin.h>
#endif

#include "sampling/lane_warps.h"
#include "validate/lanes/lane_cells.h"
#include "validate/lanes/lane_sampling.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // see sampling/lanes.h

namespace warpcheck::lane_kernels {

/// Three sets of lanes::kWidth lanes per step, independent, so that one set's
/// long latencies (divisions, square roots, the generators' multiply chains)
/// overlap with the others' work (three measured ~5% faster than two).
template <typename Kernel>
WARPCHECK_LANE void run_group(const Kernel& warp, const LaneGroup& g) {
    constexpr int W = lanes::kWidth;
    lanes::Pcg32Lanes rng_a, rng_b, rng_c;
    std::memcpy(&rng_a.state, g.state, sizeof rng_a.state);
    std::memcpy(&rng_a.inc, g.inc, sizeof rng_a.inc);
    std::memcpy(&rng_b.state, g.state + W, sizeof rng_b.state);
    std::memcpy(&rng_b.inc, g.inc + W, sizeof rng_b.inc);
    std::memcpy(&rng_c.state, g.state + 2 * W, sizeof rng_c.state);
    std::memcpy(&rng_c.inc, g.inc + 2 * W, sizeof rng_c.inc);
    const chi2::LanePlan& plan = *g.plan;
    bool all_lanes = true;
    for (int l = 0; l < kLaneGroupChunks; ++l) all_lanes = all_lanes && g.samples[l] == g.steps;
    const unsigned char* const zero = g.zero_cells;
    uint64_t* const counts = g.counts;
    std::size_t unclassified = 0;
    alignas(64) int64_t cell[kLaneGroupChunks];
    [[maybe_unused]] alignas(64) int64_t either[W];
    for (uint32_t i = 0; i < g.steps; ++i) {
        // As draw_inputs: u.x from the first 64 bits, u.y from the next.
        const lanes::F32 a0 = lanes::uniform_float_from_bits(rng_a.next_u64());
        const lanes::F32 a1 = lanes::uniform_float_from_bits(rng_a.next_u64());
        const lanes::F32 b0 = lanes::uniform_float_from_bits(rng_b.next_u64());
        const lanes::F32 b1 = lanes::uniform_float_from_bits(rng_b.next_u64());
        const lanes::F32 c0 = lanes::uniform_float_from_bits(rng_c.next_u64());
        const lanes::F32 c1 = lanes::uniform_float_from_bits(rng_c.next_u64());
        const lanes::Points pa = warp(a0, a1), pb = warp(b0, b1), pc = warp(c0, c1);
        const lanes::I64 ca = lane_cells(plan, pa.x, pa.y, pa.z), cb = lane_cells(plan, pb.x, pb.y, pb.z),
                         cc = lane_cells(plan, pc.x, pc.y, pc.z);
        std::memcpy(cell, &ca, sizeof ca);
        std::memcpy(cell + W, &cb, sizeof cb);
        std::memcpy(cell + 2 * W, &cc, sizeof cc);
        const lanes::I64 both = ca | cb | cc;  // negative where a set left a sample unclassified
#ifdef __AVX512DQ__
        const bool any_unclassified = _mm512_movepi64_mask(reinterpret_cast<const __m512i&>(both)) != 0;
#else
        std::memcpy(either, &both, sizeof either);
        int64_t sign = 0;
        for (int l = 0; l < W; ++l) sign |= either[l];
        const bool any_unclassified = sign < 0;
#endif
        if (all_lanes && !zero && !any_unclassified) {
            for (int l = 0; l < kLaneGroupChunks; ++l) ++counts[cell[l]];
            continue;
        }
        for (int l = 0; l < kLaneGroupChunks; ++l) {
            if (i >= g.samples[l]) continue;
            const int64_t k = cell[l];
            if (k >= 0 && !(zero && zero[k])) {
                ++counts[k];
            } else {
                const lanes::Points& p = l < W ? pa : l < 2 * W ? pb : pc;
                const int m = l % W;
                g.unclassified[unclassified++] = {p.x[m], p.y[m], p.z[m]};
            }
        }
    }
    *g.unclassified_count = unclassified;
}

// The group functions of the built-in lane forms, on each path.
#define WARPCHECK_LANE_FORMS(X) \
    X(uniform_disk_polar, UniformDiskPolarLanes) \
    X(uniform_disk_concentric, UniformDiskConcentricLanes) \
    X(cosine_hemisphere, CosineHemisphereLanes) \
    X(uniform_hemisphere, UniformHemisphereLanes) \
    X(uniform_sphere, UniformSphereLanes)

#define WARPCHECK_DECLARE_GROUP_FNS(name, Kernel) \
    void name##_avx512(const void* kernel, const LaneGroup& g); \
    void name##_portable(const void* kernel, const LaneGroup& g);
WARPCHECK_LANE_FORMS(WARPCHECK_DECLARE_GROUP_FNS)
#undef WARPCHECK_DECLARE_GROUP_FNS

}  // namespace warpcheck::lane_kernels

#pragma GCC diagnostic pop
