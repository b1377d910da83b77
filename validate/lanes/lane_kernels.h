// The lockstep loop of the vectorised chi-square path, instantiated once per
// built-in lane form in three translation units: lane_sampling.cpp (portable,
// the baseline target), lane_sampling_avx2.cpp (x86-64-v3) and
// lane_sampling_avx512.cpp (x86-64-v4), each whole file built for its target.
// The lane helpers must be compiled for the target they run on: inlined from a baseline build they arrive already split into 128-bit pieces.
// Everything here is always_inline and nothing calls out of it but libm's
// powf (lanes::pow: a library function, not an inline one; no std::vector),
// so neither the AVX-512 nor the AVX2 file emits a shared inline function that
// the linker could pick for a caller on another processor; the ctest
// lane_objects_are_isolated checks that.
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

/// The counting half of a group's step: each sample's cell incremented, the
/// samples of chunks that have run out skipped, and the ones the lanes leave
/// unclassified (or that land in a zero cell) set aside for Binning::bin.
struct StepCounter {
    const LaneGroup& g;
    bool all_lanes = true;
    std::size_t unclassified = 0;
    alignas(64) int64_t cell[kLaneGroupChunks];

    WARPCHECK_LANE explicit StepCounter(const LaneGroup& group) : g(group) {
        for (int l = 0; l < kLaneGroupChunks; ++l) all_lanes = all_lanes && g.samples[l] == g.steps;
    }
    /// Step i of the three sets of lanes: their points p and cells c.
    WARPCHECK_LANE void add(uint32_t i, const lanes::Points (&p)[3], const lanes::I64 (&c)[3]) {
        constexpr int W = lanes::kWidth;
        for (int s = 0; s < 3; ++s) std::memcpy(cell + s * W, &c[s], sizeof c[s]);
        const lanes::I64 both = c[0] | c[1] | c[2];  // negative where a set left a sample unclassified
#ifdef __AVX512DQ__
        const bool any_unclassified = _mm512_movepi64_mask(reinterpret_cast<const __m512i&>(both)) != 0;
#else
        alignas(64) int64_t either[W];
        std::memcpy(either, &both, sizeof either);
        int64_t sign = 0;
        for (int l = 0; l < W; ++l) sign |= either[l];
        const bool any_unclassified = sign < 0;
#endif
        const unsigned char* const zero = g.zero_cells;
        if (all_lanes && !zero && !any_unclassified) {
            for (int l = 0; l < kLaneGroupChunks; ++l) ++g.counts[cell[l]];
            return;
        }
        for (int l = 0; l < kLaneGroupChunks; ++l) {
            if (i >= g.samples[l]) continue;
            const int64_t k = cell[l];
            if (k >= 0 && !(zero && zero[k])) {
                ++g.counts[k];
            } else {
                const lanes::Points& q = p[l / W];
                const int m = l % W;
                g.unclassified[unclassified++] = {q.x[m], q.y[m], q.z[m]};
            }
        }
    }
    WARPCHECK_LANE void finish() const { *g.unclassified_count = unclassified; }
};

/// The group's generators: three sets of lanes::kWidth lanes.
WARPCHECK_LANE void load_generators(const LaneGroup& g, lanes::Pcg32Lanes (&rng)[3]) {
    constexpr int W = lanes::kWidth;
    for (int s = 0; s < 3; ++s) {
        std::memcpy(&rng[s].state, g.state + s * W, sizeof rng[s].state);
        std::memcpy(&rng[s].inc, g.inc + s * W, sizeof rng[s].inc);
    }
}

/// Three sets of lanes::kWidth lanes per step, independent, so that one set's
/// long latencies (divisions, square roots, the generators' multiply chains)
/// overlap with the others' work (three measured ~5% faster than two).
template <typename Kernel>
WARPCHECK_LANE void run_group(const Kernel& warp, const LaneGroup& g) {
    lanes::Pcg32Lanes rng[3];
    load_generators(g, rng);
    const chi2::LanePlan& plan = *g.plan;
    StepCounter counter(g);
    for (uint32_t i = 0; i < g.steps; ++i) {
        lanes::Points p[3];
        lanes::I64 c[3];
        for (int s = 0; s < 3; ++s) {
            // As draw_inputs: u.x from the first 64 bits, u.y from the next.
            const lanes::F32 u0 = lanes::uniform_float_from_bits(rng[s].next_u64());
            const lanes::F32 u1 = lanes::uniform_float_from_bits(rng[s].next_u64());
            p[s] = warp(u0, u1);
            c[s] = lane_cells(plan, p[s].x, p[s].y, p[s].z);
        }
        counter.add(i, p, c);
    }
    counter.finish();
}

/// Steps per block of the planar group: 64 x 24 samples, five arrays of them
/// (30 KB on the stack), so a block's draws, points and cells stay in cache.
inline constexpr uint32_t kPlanarSteps = 64;

/// WarpCase::sample_planar of the case `warp` points to (defined in the baseline build, lane_sampling.cpp).
void sample_planar(const void* warp, const float* u0, const float* u1, float* x, float* y, float* z, std::size_t n);

/// The group of a warp without a lane form: the lanes draw a block of inputs,
/// the warp's own scalar sample maps the block (WarpCase::sample_planar, one
/// call per block, its loop over the samples in the case's own code), and the
/// lanes bin the points. The same draws and cells as run_group.
WARPCHECK_LANE void run_planar_group(const void* warp, const LaneGroup& g) {
    constexpr int W = lanes::kWidth, G = kLaneGroupChunks;
    constexpr std::size_t kBlock = std::size_t{kPlanarSteps} * G;
    lanes::Pcg32Lanes rng[3];
    load_generators(g, rng);
    alignas(64) float u0[kBlock], u1[kBlock], x[kBlock], y[kBlock], z[kBlock];
    StepCounter counter(g);
    for (uint32_t base = 0; base < g.steps; base += kPlanarSteps) {
        const uint32_t n = g.steps - base < kPlanarSteps ? g.steps - base : kPlanarSteps;
        for (uint32_t i = 0; i < n; ++i)
            for (int s = 0; s < 3; ++s) {  // as draw_inputs: u.x from the first 64 bits, u.y from the next
                const lanes::F32 a = lanes::uniform_float_from_bits(rng[s].next_u64());
                const lanes::F32 b = lanes::uniform_float_from_bits(rng[s].next_u64());
                std::memcpy(u0 + i * G + s * W, &a, sizeof a);
                std::memcpy(u1 + i * G + s * W, &b, sizeof b);
            }
        sample_planar(warp, u0, u1, x, y, z, std::size_t{n} * G);
        for (uint32_t i = 0; i < n; ++i) {
            lanes::Points p[3];
            lanes::I64 c[3];
            for (int s = 0; s < 3; ++s) {
                const std::size_t at = i * G + s * W;
                std::memcpy(&p[s].x, x + at, sizeof p[s].x);
                std::memcpy(&p[s].y, y + at, sizeof p[s].y);
                std::memcpy(&p[s].z, z + at, sizeof p[s].z);
                c[s] = lane_cells(*g.plan, p[s].x, p[s].y, p[s].z);
            }
            counter.add(base + i, p, c);
        }
    }
    counter.finish();
}

// The group functions of the built-in lane forms, on each path: those without
// parameters, and those with (the kernel object holds them).
#define WARPCHECK_PLAIN_LANE_FORMS(X) \
    X(uniform_disk_polar, UniformDiskPolarLanes) \
    X(uniform_disk_concentric, UniformDiskConcentricLanes) \
    X(cosine_hemisphere, CosineHemisphereLanes) \
    X(uniform_hemisphere, UniformHemisphereLanes) \
    X(uniform_sphere, UniformSphereLanes)
#define WARPCHECK_LANE_FORMS(X) \
    WARPCHECK_PLAIN_LANE_FORMS(X) \
    X(uniform_cone, UniformConeLanes) \
    X(cosine_power_hemisphere, CosinePowerHemisphereLanes) \
    X(trowbridge_reitz_normals, TrowbridgeReitzNormalsLanes) \
    X(trowbridge_reitz_visible, TrowbridgeReitzVisibleNormalsLanes)

// The group functions of warps without a lane form (run_planar_group), on each path.
void planar_avx512(const void* warp, const LaneGroup& g);
void planar_avx2(const void* warp, const LaneGroup& g);
void planar_portable(const void* warp, const LaneGroup& g);

#define WARPCHECK_DECLARE_GROUP_FNS(name, Kernel) \
    void name##_avx512(const void* kernel, const LaneGroup& g); \
    void name##_avx2(const void* kernel, const LaneGroup& g); \
    void name##_portable(const void* kernel, const LaneGroup& g);
WARPCHECK_LANE_FORMS(WARPCHECK_DECLARE_GROUP_FNS)
#undef WARPCHECK_DECLARE_GROUP_FNS

}  // namespace warpcheck::lane_kernels

#pragma GCC diagnostic pop
