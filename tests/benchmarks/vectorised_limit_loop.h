// The speed limit of the chi-square check's draw + warp + bin (issue 27): a
// plain loop that the compiler vectorises by itself, for the cosine hemisphere,
// against which bench_chi2's BM_DrawWarpBinVsLimitLoop measures the lane path.
#pragma once

#include <cstdint>
#include <vector>

#include "chi2/binning.h"

namespace warpcheck::bench {

/// Draws `samples` points of the cosine hemisphere and counts them into
/// `counts` (resized to the plan's rows x cols cells, cell = row * cols + column,
/// as lane_cells numbers them): 16 PCG32 streams stepped in lockstep in plain
/// arrays, one 32-bit draw per coordinate (its top 24 bits times 2^-24; the
/// check draws 64 bits per coordinate, so twice the generator steps); the
/// concentric map with the sine and cosine of the wedge angle w in [-pi/4,
/// pi/4] by Taylor polynomials in float, not the project's sin_cos (a limit,
/// not the same bits: the terms end at w^9 and w^10, the next below 2e-9); the
/// cell of the point found as lane_cells finds it but in float (row by z,
/// column by the signs, the |x|, |y| comparison and the octant's tan edges
/// against min(|x|, |y|) / max(|x|, |y|), compared as a product), without atan2,
/// all in one loop body per lane. Built for x86-64-v4 where the processor has it, as the lane
/// path is, else for the baseline. `plan` must be a spherical cap's.
void vectorised_limit_loop(uint64_t samples, const chi2::LanePlan& plan, std::vector<uint64_t>& counts);

}  // namespace warpcheck::bench
