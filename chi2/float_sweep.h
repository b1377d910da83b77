// Exhaustive float histograms: run a function over every input of a range (up
// to all 2^32 values of a u32) and count, exactly, how often each float comes
// out, summarised per binade against the ideal measure. Pure counting: no
// printing, no verdicts (validate/checks/exhaustive/exhaustive_check.cpp judges). Knows no
// warps: it takes the function to sweep as a block callback.
//
// Ideal measure: a uniform real of [a,b) rounded down to a float, so the ideal
// multiplicity of a float x of [a,b) is count * (next_float_up(x) - x) / (b - a):
// constant within a binade (for negative floats the binade is the magnitude
// range (2^e, 2^(e+1)], where that spacing is constant).
//
// Method: the inputs are split into fixed chunks (2^22 inputs, whatever the
// thread count). Each chunk evaluates blocks of outputs and counts runs of
// equal outputs; runs that touch a chunk border are merged in chunk order. For a
// monotone function that is the exact histogram in O(1) memory. If an output is
// ever smaller than the one before (a non-monotone step), equal outputs may be
// far apart, and the counts are redone exactly: by sorting all outputs when
// there are at most 2^26 inputs, otherwise by counting windows of binades. The
// first pass stops once a chunk steps down (that chunk stops, and chunks not
// started are skipped): the recount counts every step down itself, in input
// order. The recount's first window takes the 64 binades
// where most outputs lie (ranked by f on 2^16 inputs evenly spread over the
// range: a run of 16 at each of 4096 points), with a one-byte counter per float
// (2^29 counters, 512 MiB; a counter that wraps records the wrap, at most
// inputs / 256 records, 64 MiB); the outputs outside it are kept (2^14 per
// chunk of the sweep, in one budget shared by all chunks: 64 MiB for 2^32
// inputs) and counted by sorting. So a map whose outputs lie in 64 binades or
// in few floats beyond them (any map into [0,1) with outputs of at least
// 2^-64, say) is recounted with one more run of f, within 1 GiB. If more
// outputs than that lie outside the first window, the remaining binades are
// counted in further windows, one more run of f each. A window pass works in
// rounds of 16 chunks: each chunk appends its outputs' counter indices to
// blocks by the slice of counters they fall in (radix partitioning; at most
// 257 slices, each a power of two of at least 2^16 counters: at most 2 MiB for
// the default window of 64 binades; written through a cache line per slice
// with streaming stores; 272 MiB a round), then each slice adds the blocks of
// the round on one thread, so the increments stay within L2 and need no locks.
// Every figure is an integer count, or computed at the end from
// integer counts, so results do not depend on threads or on how the recount
// was done.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "chi2/parallel.h"

namespace warpcheck::chi2 {

/// out[i] = f(first + i) for i in [0, n).
using FloatBlockFn = std::function<void(uint64_t first, std::size_t n, float* out)>;

/// Optionally, the same f fused with the first pass's run scan, so that a
/// monotone sweep need not store its outputs (validate/api/exhaustive_sweep.h
/// builds one for an inlined sampler): evaluates f(first + j) for j in [0, n)
/// and, for every j whose output's bits differ from those of the output before
/// it (for j = 0: `previous`), in increasing order, writes base + j to
/// positions and the bits to bits (both need n + 16 entries); sets `last` to
/// the bits of f(first + n - 1) and returns how many it wrote. It must agree
/// with the FloatBlockFn it is given with.
using FloatBordersFn = std::function<std::size_t(uint64_t first, std::size_t n, uint32_t previous, uint32_t base,
                                                 uint32_t* positions, uint32_t* bits, uint32_t& last)>;

/// Counts for one binade of the interval.
struct BinadeCount {
    int sign = 1;        ///< +1 or -1
    int exponent = 0;    ///< magnitudes in [2^e, 2^(e+1)) (negative: (2^e, 2^(e+1)]); -127: the denormals
    float first = 0.0f;  ///< smallest float of the binade inside the interval
    float last = 0.0f;   ///< largest float of the binade inside the interval
    uint64_t floats = 0;    ///< floats of the binade inside the interval
    uint64_t distinct = 0;  ///< how many of them were produced
    uint64_t inputs = 0;    ///< inputs that produced one of them
    double ideal = 0.0;     ///< ideal multiplicity of each of them
    uint64_t min_multiplicity = 0;  ///< over all its floats in the interval: 0 if one is never produced
    uint64_t max_multiplicity = 0;
    /// The first float of the binade (its power of two, where the spacing
    /// changes, so round-to-nearest gives it a share of both spacings): its
    /// multiplicity, 0 if not produced or not in the interval.
    uint64_t edge_multiplicity = 0;
    /// Among its produced floats other than the first: one with the largest
    /// multiplicity and one with the smallest (the first in order on ties), and
    /// those multiplicities; 0 when none is produced.
    float most_produced = 0.0f, least_produced = 0.0f;
    uint64_t most_multiplicity = 0, least_multiplicity = 0;
    /// Over the other produced floats with an even (odd) significand; 0/0 when
    /// there are none.
    uint64_t min_even = 0, max_even = 0, min_odd = 0, max_odd = 0;
    double abs_deviation = 0.0;  ///< sum over its floats of |multiplicity - ideal|

    /// "257/255" (even/odd significands) when every float is produced and,
    /// apart from the binade's first float, the multiplicity depends only on
    /// the parity, with different values; "256" when all those are equal; empty
    /// otherwise.
    std::string pattern() const;
};

/// An output outside the interval and how many inputs produced it.
struct OutsideValue {
    float value = 0.0f;
    uint64_t inputs = 0;
};

struct SweepSummary {
    uint64_t inputs = 0;              ///< inputs evaluated
    uint64_t distinct = 0;            ///< distinct outputs (-0 counts as 0; NaNs count as one)
    uint64_t distinct_inside = 0;     ///< distinct outputs inside [a,b)
    uint64_t outside_distinct = 0;    ///< distinct outputs outside [a,b)
    uint64_t outside_inputs = 0;      ///< inputs producing them
    uint64_t floats_in_interval = 0;  ///< floats of [a,b) (one zero)
    uint64_t never_produced = 0;      ///< floats of [a,b) no input produced
    uint64_t non_monotone_steps = 0;  ///< i with f(i+1) < f(i) (NaN steps count as decreasing)
    bool exact_fallback = false;      ///< whether the non-monotone recount ran
    int recount_passes = 0;           ///< runs of f over every input in that recount (0: it did not run)
    /// Wall seconds of the run-counting pass and of the non-monotone recount.
    double runs_seconds = 0.0, recount_seconds = 0.0;
    /// Total variation distance between the output distribution and the ideal
    /// measure: half the sum over all floats of |count/inputs - ideal/inputs|,
    /// outside outputs included (their ideal is 0).
    double tv_distance = 0.0;
    /// The reach: smallest and largest output inside [a,b) (both 0 when none is).
    float lowest_inside = 0.0f, highest_inside = 0.0f;
    std::vector<OutsideValue> outside_values;  ///< the 16 smallest outside outputs, increasing
    std::vector<BinadeCount> binades;          ///< every binade meeting [a,b), in increasing order

    /// How many inputs produced the outside output x; 0 if x is not among
    /// outside_values.
    uint64_t outside_inputs_of(float x) const;
    /// The binade with this sign and exponent, or nullptr.
    const BinadeCount* binade(int sign, int exponent) const;
};

/// How the non-monotone recount works; the defaults are the stated bounds.
/// Tests lower them to reach the window recount on a reduced range.
struct SweepLimits {
    uint64_t sort_limit = uint64_t{1} << 26;  ///< recount by sorting up to this many inputs (4 bytes each)
    int window_binades = 64;                  ///< binades per counting window: 2^23 1-byte counters each
    /// Take the portable loops even where the CPU has AVX-512 (tests check
    /// that both give the same counts).
    bool portable = false;
};

/// Sweeps f over inputs [0, count), count <= 2^32, against [a,b) (finite a < b).
SweepSummary exhaustive_sweep(const FloatBlockFn& f, uint64_t count, float a, float b,
                              const ParallelFor& parallel_for, const SweepLimits& limits = {});
/// The same, with f's fused run scan (empty: none) for the first pass.
SweepSummary exhaustive_sweep(const FloatBlockFn& f, const FloatBordersFn& borders, uint64_t count, float a, float b,
                              const ParallelFor& parallel_for, const SweepLimits& limits = {});

}  // namespace warpcheck::chi2
