// The vectorised chi-square path: draw, warp and bin 24 samples at once (three sets of 8 lanes).
//
// The chi-square check draws its samples in chunks of 4,096, chunk c from its
// own stream ctx.chunk_rng(c) (validate/checks/check.h). Here 24 consecutive
// chunks run in lockstep, one per lane: lane l is a copy of chunk 24 g + l's
// Pcg32, its inputs are drawn as draw_inputs draws them, warped by the lane
// form of the warp (sampling/lane_warps.h) and binned by lane_cells (validate/lanes/lane_cells.h). The
// few samples the lanes do not classify (NaN, outside the domain, in a cell
// where the density integrates to zero) go to Binning::bin one by one. So the
// histogram is the one the scalar path builds, count for count, for any
// thread count and on either code path:
//   - AVX-512 (x86-64-v4), which the chi-square check uses where the processor
//     has it;
//   - AVX2 (x86-64-v3 without FMA), which it uses where the processor has
//     AVX2 and not AVX-512 (elsewhere it keeps its scalar chunk path, the
//     faster there);
//   - portable: the same source compiled for the baseline target, which the
//     tests hold to the same bits (LanePath::Portable).
// tests/validate/lanes/test_lane_sampling.cpp holds every path to the scalar one.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "chi2/binning.h"
#include "chi2/parallel.h"
#include "sampling/lanes.h"
#include "sampling/trowbridge_reitz.h"
#include "sampling/pcg32.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

/// Chunks run in lockstep: three sets of lanes::kWidth lanes.
inline constexpr int kLaneGroupChunks = 3 * lanes::kWidth;

/// One lockstep run: up to kLaneGroupChunks chunks, lane l drawing from (state[l], inc[l]).
struct LaneGroup {
    const chi2::LanePlan* plan = nullptr;
    uint64_t state[kLaneGroupChunks] = {}, inc[kLaneGroupChunks] = {};
    uint32_t samples[kLaneGroupChunks] = {};  ///< samples of lane l's chunk; 0 for a lane without one
    uint32_t steps = 0;         ///< the largest of samples[]
    const unsigned char* zero_cells = nullptr;  ///< per cell, 1 where the density integrates to zero; or null
    uint64_t* counts = nullptr;                 ///< the histogram's cell counts, incremented
    /// Samples left to Binning::bin: room for kLaneGroupChunks * steps, and how many were written.
    WarpOutput* unclassified = nullptr;
    std::size_t* unclassified_count = nullptr;
};

/// A warp's lane form, compiled for each path.
struct LaneSampler {
    using GroupFn = void (*)(const void* kernel, const LaneGroup& group);
    const void* kernel = nullptr;
    GroupFn avx512 = nullptr;
    GroupFn avx2 = nullptr;
    GroupFn portable = nullptr;
};

/// The lane forms of the built-in warps of sampling/lane_warps.h. Those with
/// parameters are made once per parameter value and live as long as the process.
namespace builtin_lanes {
const LaneSampler& uniform_disk_polar();
const LaneSampler& uniform_disk_concentric();
const LaneSampler& cosine_hemisphere();
const LaneSampler& uniform_hemisphere();
const LaneSampler& uniform_sphere();
const LaneSampler& uniform_cone(float cos_theta_max);
const LaneSampler& cosine_power_hemisphere(float exponent);
const LaneSampler& trowbridge_reitz_normals(float alpha_x, float alpha_y);
const LaneSampler& trowbridge_reitz_visible(const TrowbridgeReitzVisibleNormals& warp);
}  // namespace builtin_lanes

/// The lane sampler of a Uniform2D warp without a lane form: the lanes draw
/// and bin, and the warp's own sample maps the points in blocks of 1,536
/// (WarpCase::sample_planar), so the histogram is the scalar path's. It refers
/// to `warp`, which must outlive it.
LaneSampler planar_lane_sampler(const WarpCase& warp);

enum class LanePath { Auto, Avx512, Avx2, Portable };

/// Whether this processor runs the AVX-512 path (AVX-512 F, CD, BW, DQ, VL).
bool avx512_available();
/// Whether this processor runs the AVX2 path (x86-64-v3: AVX2, BMI1/2, F16C, LZCNT, MOVBE).
bool avx2_available();
/// The path Auto picks here: AVX-512, else AVX2, else portable.
LanePath auto_lane_path();
/// Whether Auto picks a vector path here (AVX-512 or AVX2), which the
/// chi-square check prefers to its scalar chunks; the portable build is slower.
bool vector_lane_path_available();
const char* lane_path_name(LanePath path);

/// The histogram of `samples` samples of a 2D warp, drawn in chunks of
/// chunk_size, chunk c from chunk_rng(c), exactly as chi2::sample_histogram
/// with draw_inputs and WarpCase::sample would build it. `binning` must have a
/// lane_plan(). Path Avx512 or Avx2 on a processor without it throws std::runtime_error.
chi2::Histogram lane_histogram(const chi2::Binning& binning, uint64_t samples, std::size_t chunk_size,
                               const std::function<Pcg32(uint64_t chunk)>& chunk_rng, const LaneSampler& sampler,
                               std::span<const unsigned char> zero_cells, const chi2::ParallelFor& parallel_for,
                               LanePath path = LanePath::Auto);

}  // namespace warpcheck
