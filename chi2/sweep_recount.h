// The exact recount of a non-monotone function by the exhaustive float sweep
// (chi2/float_sweep.h explains when and how): by sorting every output, or by
// windows of one-byte counters filled by radix partitioning. Internal to chi2.
#pragma once

#include <array>
#include <cstdint>

#include "chi2/float_sweep.h"
#include "chi2/sweep_counts.h"

namespace warpcheck::chi2::sweep {

/// What a recount found besides the counts: the steps down of f over its
/// inputs in order (i with f(i+1) < f(i) as keys: the first pass may stop
/// counting them), and the runs of f over every input that it took.
struct RecountTrace {
    uint64_t steps_down = 0;
    int passes = 0;
};

/// Exact recount of f over inputs [0, count) by sorting all its outputs
/// (4 bytes each), into total.
RecountTrace recount_sorted(const FloatBlockFn& f, uint64_t count, const ParallelFor& parallel_for, RunCounter& total);

/// Exact recount of f over inputs [0, count) by windows of binades, into
/// total. `mass` ranks the binades (inputs seen there, or a sample of them);
/// the binades that outputs reach are found by the recount's first pass.
RecountTrace recount_windows(const FloatBlockFn& f, uint64_t count, const ParallelFor& parallel_for,
                             const std::array<uint64_t, kGroups>& mass, int window_binades, RunCounter& total);

}  // namespace warpcheck::chi2::sweep
