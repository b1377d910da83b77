// The exact recount of a non-monotone function by the exhaustive float sweep
// (chi2/float_sweep.h explains when and how): by sorting every output, or by
// windows of one-byte counters filled by radix partitioning. Internal to chi2.
#pragma once

#include <array>
#include <cstdint>

#include "chi2/float_sweep.h"
#include "chi2/sweep_counts.h"

namespace warpcheck::chi2::sweep {

/// Exact recount of f over inputs [0, count) by sorting all its outputs
/// (4 bytes each), into total.
void recount_sorted(const FloatBlockFn& f, uint64_t count, const ParallelFor& parallel_for, RunCounter& total);

/// Exact recount of f over inputs [0, count) by windows of binades, into
/// total. `mass` ranks the binades (inputs seen there, or a sample of them);
/// `reach` marks every binade an output may lie in.
void recount_windows(const FloatBlockFn& f, uint64_t count, const ParallelFor& parallel_for,
                     const std::array<uint64_t, kGroups>& mass, const std::array<uint8_t, kGroups>& reach,
                     int window_binades, RunCounter& total);

}  // namespace warpcheck::chi2::sweep
