#include "chi2/float_sweep.h"
#include "chi2/run_borders.h"
#include "chi2/sweep_counts.h"
#include "chi2/sweep_recount.h"

// The run scan and the summary; the counting model is chi2/sweep_counts.h, the
// exact recount of non-monotone functions chi2/sweep_recount.cpp.

#include <algorithm>
#include <atomic>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#if defined(__x86_64__)
#include <immintrin.h>
#endif
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace warpcheck::chi2 {
using namespace sweep;
namespace {

struct Run {
    uint32_t key = 0;
    uint64_t count = 0;
};

// What one chunk leaves for the in-order merge.
struct ChunkEnds {
    Run head, tail;
    bool single = false;  // the whole chunk is one run (head == tail)
    uint64_t steps_down = 0;
};

// Which code the run scan takes: AVX-512 where the CPU has every instruction
// set the border kernel is built for, unless a test asks for the portable loops
// (SweepLimits::portable). Both give the same counts.
#if defined(__x86_64__) && defined(__GNUC__)
bool have_avx512() { return detail::borders_kernel_supported(); }
#else
bool have_avx512() { return false; }
#endif

// Run borders of a block: for each j in [0, n) where the bits of x[j] differ
// from those of x[j - 1] (x[-1] must be readable), in increasing order, writes
// base + j to positions and the bits of x[j] to bits; returns how many. Both
// arrays need n + 16 entries; n is a multiple of 64. Equal keys with different
// bits (-0 and +0, NaNs) are merged by the caller.
std::size_t borders_portable(const float* x, std::size_t n, uint32_t base, uint32_t* positions, uint32_t* bits) {
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const uint32_t b = float_to_bits(x[i]);
        positions[count] = base + static_cast<uint32_t>(i);
        bits[count] = b;
        count += b != float_to_bits(x[i - 1]);
    }
    return count;
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx512f"))) inline __m512i float_keys_avx512(__m512i bits) {
    const __m512i sign = _mm512_set1_epi32(static_cast<int>(kFloatSignMask));
    const __m512i magnitude = _mm512_and_si512(bits, _mm512_set1_epi32(0x7fffffff));
    const __mmask16 negative = _mm512_test_epi32_mask(bits, sign);
    __m512i key = _mm512_mask_xor_epi32(_mm512_or_si512(bits, sign), negative, bits, _mm512_set1_epi32(-1));
    key = _mm512_mask_mov_epi32(key, _mm512_cmpeq_epu32_mask(magnitude, _mm512_setzero_si512()), sign);
    return _mm512_mask_mov_epi32(key, _mm512_cmpgt_epu32_mask(magnitude, _mm512_set1_epi32(0x7f800000)),
                                 _mm512_set1_epi32(-1));
}

// x must be 64-byte aligned (the kernel is chi2/run_borders.h).
__attribute__((target(WARPCHECK_BORDERS_TARGET))) std::size_t borders_avx512(const float* x, std::size_t n,
                                                                             uint32_t base, uint32_t* positions,
                                                                             uint32_t* bits) {
    detail::BorderList out{positions, bits};
    for (std::size_t i = 0; i < n; i += 64) {
        const __m512i previous = _mm512_set1_epi32(static_cast<int>(float_to_bits(x[i - 1])));
        detail::append_borders_64(_mm512_load_si512(x + i), _mm512_load_si512(x + i + 16),
                                  _mm512_load_si512(x + i + 32), _mm512_load_si512(x + i + 48), previous,
                                  base + static_cast<uint32_t>(i), out);
    }
    return out.count;
}

// Entries 1..count hold the bits of each border's output: turns them into keys
// (entry 0 is a key already) and returns how many keys are below the one
// before (steps down); `equal` says whether one equals it.
__attribute__((target("avx512f,popcnt"))) uint64_t keys_and_steps_down_avx512(uint32_t* keys, std::size_t count,
                                                                               bool& equal) {
    uint64_t down = 0;
    __mmask16 any_equal = 0;
    __m512i previous = _mm512_set1_epi32(static_cast<int>(keys[0]));
    for (std::size_t k = 1; k <= count; k += 16) {
        const __mmask16 valid =
            count + 1 - k >= 16 ? __mmask16{0xffff} : static_cast<__mmask16>((1u << (count + 1 - k)) - 1);
        const __m512i key = float_keys_avx512(_mm512_maskz_loadu_epi32(valid, keys + k));
        _mm512_mask_storeu_epi32(keys + k, valid, key);
        const __m512i before = _mm512_maskz_alignr_epi32(0xffff, key, previous, 15);
        down += static_cast<uint64_t>(std::popcount(static_cast<unsigned>(_mm512_mask_cmplt_epu32_mask(valid, key, before))));
        any_equal |= _mm512_mask_cmpeq_epu32_mask(valid, key, before);
        previous = key;
    }
    equal = any_equal != 0;
    return down;
}
#endif

uint64_t keys_and_steps_down_portable(uint32_t* keys, std::size_t count, bool& equal) {
    uint64_t down = 0;
    bool any_equal = false;
    for (std::size_t k = 1; k <= count; ++k) {
        keys[k] = float_key(bits_to_float(keys[k]));
        down += keys[k] < keys[k - 1];
        any_equal |= keys[k] == keys[k - 1];
    }
    equal = any_equal;
    return down;
}

// Per-lane accumulators of the running binade's runs (the fast part of
// GroupCounts). The AVX-512 scan gives lane l the runs l, l + 16, ... of each
// group of 16; the portable scan uses lane 0 only. Within a lane the first run
// in input order wins a tie (strict comparisons); flush() picks among lanes by
// multiplicity, then position, so both scans keep the first run in input order.
// Multiplicities and their sums fit 32 bits: a chunk has 2^22 inputs.
struct LaneState {
    static constexpr int kLanes = 16;
    alignas(64) uint32_t min_m[2][kLanes], min_pos[2][kLanes], min_key[2][kLanes];
    alignas(64) uint32_t max_m[2][kLanes], max_pos[2][kLanes], max_key[2][kLanes];
    alignas(64) uint32_t lo[kLanes], hi[kLanes], sum[kLanes], sum_ge[kLanes];
    uint64_t distinct = 0, n_ge = 0;

    LaneState() { reset(); }
    void reset() {
        for (int p = 0; p < 2; ++p) {
            std::fill_n(min_m[p], kLanes, std::numeric_limits<uint32_t>::max());
            std::fill_n(max_m[p], kLanes, 0u);
            std::fill_n(min_pos[p], kLanes, 0u);
            std::fill_n(max_pos[p], kLanes, 0u);
            std::fill_n(min_key[p], kLanes, 0u);
            std::fill_n(max_key[p], kLanes, 0u);
        }
        std::fill_n(lo, kLanes, std::numeric_limits<uint32_t>::max());
        std::fill_n(hi, kLanes, 0u);
        std::fill_n(sum, kLanes, 0u);
        std::fill_n(sum_ge, kLanes, 0u);
        distinct = n_ge = 0;
    }
};

// Counts the runs of one chunk. Per block of outputs: the run borders (position
// and key of each run's first output), then the runs, 16 at a time while they
// stay in the running binade's fast range (its floats inside [a,b) but its
// first one), whose counters live in LaneState; the first float of a binade (a
// power of two, where the spacing changes) and every change of binade go
// through the slow path.
class ChunkScanner {
public:
    ChunkScanner(const SweepFrame& frame, RunCounter& out, bool avx512) : frame_(frame), out_(out), avx512_(avx512) {}

    // f on the chunk's inputs [first, first + n); `fused`, if not empty, is f
    // fused with the border scan (FloatBordersFn).
    ChunkEnds scan(const FloatBlockFn& f, const FloatBordersFn& fused, uint64_t first, uint64_t n) {
        // values[-1] holds the last value of the previous block. Border lists:
        // entry 0 is the run in progress (its start and key), then the borders.
        // Outputs at a 64-byte boundary (the border scan loads whole cache lines).
        std::vector<float> buffer(kBlockSize + 64 + 16);
        float* values = buffer.data() + 16;
        values += (64 - reinterpret_cast<std::uintptr_t>(values) % 64) % 64 / sizeof(float);
        std::vector<uint32_t> positions(kBlockSize + 32), keys(kBlockSize + 32);
        ChunkEnds ends;
        // The chunk's first output starts the first run.
        f(first, 1, values);
        uint32_t last_bits = float_to_bits(values[0]);  // of the last output evaluated
        positions[0] = 0;
        keys[0] = float_key(values[0]);
        for (uint64_t done = 0; done < n;) {
            const auto len = static_cast<std::size_t>(std::min<uint64_t>(kBlockSize, n - done));
            std::size_t count = 0;
            if (fused) {
                count = fused(first + done, len, last_bits, static_cast<uint32_t>(done), positions.data() + 1,
                              keys.data() + 1, last_bits);
            } else {
                f(first + done, len, values);
                values[-1] = bits_to_float(last_bits);
                last_bits = float_to_bits(values[len - 1]);
                const std::size_t padded = (len + 63) / 64 * 64;
                for (std::size_t i = len; i < padded; ++i) values[i] = values[len - 1];  // no borders in the padding
                count = block_borders(values, padded, static_cast<uint32_t>(done), positions.data() + 1,
                                      keys.data() + 1);
            }
            bool equal = false;
            // Dropping a border between equal keys leaves the steps down as they are.
            ends.steps_down += block_keys_and_steps_down(keys.data(), count, equal);
            // Non-monotone: the sweep will be recounted (count_runs keeps
            // nothing of this pass then), so the chunk stops here.
            if (ends.steps_down > 0) return ends;
            if (equal) count = merge_equal_keys(positions.data(), keys.data(), count);
            std::size_t start = 0;  // the first run done in this block
            if (!have_head_ && count > 0) {
                ends.head = Run{keys[0], positions[1] - positions[0]};
                have_head_ = true;
                start = 1;
            }
            // Runs start..count-1 end in this block; run `count` goes on.
            add_runs(positions.data() + start, keys.data() + start, count - start);
            positions[0] = positions[count];
            keys[0] = keys[count];
            done += len;
        }
        flush();
        ends.tail = Run{keys[0], n - positions[0]};
        if (!have_head_) {
            ends.head = ends.tail;
            ends.single = true;
        }
        return ends;
    }

private:
    std::size_t block_borders(const float* x, std::size_t n, uint32_t base, uint32_t* positions, uint32_t* keys) const {
#if defined(__x86_64__) && defined(__GNUC__)
        if (avx512_) return borders_avx512(x, n, base, positions, keys);
#endif
        return borders_portable(x, n, base, positions, keys);
    }

    uint64_t block_keys_and_steps_down(uint32_t* keys, std::size_t count, bool& equal) const {
#if defined(__x86_64__) && defined(__GNUC__)
        if (avx512_) return keys_and_steps_down_avx512(keys, count, equal);
#endif
        return keys_and_steps_down_portable(keys, count, equal);
    }

    // Borders between equal keys (-0 after +0, another NaN) are no borders:
    // drops them from entries 1..count; returns the new count. Rare.
    static std::size_t merge_equal_keys(uint32_t* positions, uint32_t* keys, std::size_t count) {
        std::size_t kept = 0;
        for (std::size_t k = 1; k <= count; ++k) {
            if (keys[k] == keys[kept]) continue;
            ++kept;
            keys[kept] = keys[k];
            positions[kept] = positions[k];
        }
        return kept;
    }

    // Adds runs i in [0, n): key keys[i], multiplicity positions[i + 1] - positions[i].
    void add_runs(const uint32_t* positions, const uint32_t* keys, std::size_t n) {
        std::size_t i = 0;
        while (i < n) {
#if defined(__x86_64__) && defined(__GNUC__)
            if (avx512_) i = fast_runs_avx512(positions, keys, i, n);
            else i = fast_runs_portable(positions, keys, i, n);
#else
            i = fast_runs_portable(positions, keys, i, n);
#endif
            if (i == n) break;
            // Run i is outside the fast range: a new binade, its first float, or outside [a,b).
            const uint32_t key = keys[i];
            const int g = group_of(key);
            if (g != group_) {
                enter_group(g);
                if (key - fast_lo_ < fast_size_) continue;  // the fast loop takes it
            }
            out_.add(key, positions[i + 1] - positions[i]);
            ++i;
        }
    }

    // Runs from i on while they are in the fast range; returns the first that is not (or n).
    std::size_t fast_runs_portable(const uint32_t* positions, const uint32_t* keys, std::size_t i, std::size_t n) {
        LaneState& s = lanes_;
        const auto ceiling = static_cast<uint32_t>(std::min<uint64_t>(ceiling_, std::numeric_limits<uint32_t>::max()));
        for (; i < n; ++i) {
            const uint32_t key = keys[i];
            if (key - fast_lo_ >= fast_size_) return i;
            const uint32_t m = positions[i + 1] - positions[i], pos = positions[i];
            const uint32_t odd = (key ^ parity_flip_) & 1u;
            ++s.distinct;
            s.sum[0] += m;
            s.lo[0] = std::min(s.lo[0], key);
            s.hi[0] = std::max(s.hi[0], key);
            if (m < s.min_m[odd][0]) {
                s.min_m[odd][0] = m;
                s.min_pos[odd][0] = pos;
                s.min_key[odd][0] = key;
            }
            if (m > s.max_m[odd][0]) {
                s.max_m[odd][0] = m;
                s.max_pos[odd][0] = pos;
                s.max_key[odd][0] = key;
            }
            const uint32_t ge = m >= ceiling ? 1u : 0u;
            s.n_ge += ge;
            s.sum_ge[0] += m & (0u - ge);
        }
        return n;
    }

#if defined(__x86_64__) && defined(__GNUC__)
    __attribute__((target("avx512f,popcnt"))) std::size_t fast_runs_avx512(const uint32_t* positions,
                                                                          const uint32_t* keys, std::size_t i,
                                                                          std::size_t n) {
        LaneState& s = lanes_;
        __m512i min_m[2], min_pos[2], min_key[2], max_m[2], max_pos[2], max_key[2];
        for (int p = 0; p < 2; ++p) {
            min_m[p] = _mm512_load_si512(s.min_m[p]);
            min_pos[p] = _mm512_load_si512(s.min_pos[p]);
            min_key[p] = _mm512_load_si512(s.min_key[p]);
            max_m[p] = _mm512_load_si512(s.max_m[p]);
            max_pos[p] = _mm512_load_si512(s.max_pos[p]);
            max_key[p] = _mm512_load_si512(s.max_key[p]);
        }
        __m512i lo = _mm512_load_si512(s.lo), hi = _mm512_load_si512(s.hi);
        __m512i sum = _mm512_load_si512(s.sum), sum_ge = _mm512_load_si512(s.sum_ge);
        uint64_t distinct = 0, n_ge = 0;
        const __m512i fast_lo = _mm512_set1_epi32(static_cast<int>(fast_lo_));
        const __m512i fast_size = _mm512_set1_epi32(static_cast<int>(fast_size_));
        const __m512i ceiling = _mm512_set1_epi32(
            static_cast<int>(std::min<uint64_t>(ceiling_, std::numeric_limits<uint32_t>::max())));
        const __m512i one = _mm512_set1_epi32(1);
        const __mmask16 flip = parity_flip_ ? 0xffff : 0;
        while (i < n) {
            const __mmask16 valid = n - i >= 16 ? __mmask16{0xffff} : static_cast<__mmask16>((1u << (n - i)) - 1);
            const __m512i key = _mm512_maskz_loadu_epi32(valid, keys + i);
            const __m512i pos = _mm512_maskz_loadu_epi32(valid, positions + i);
            const __m512i m = _mm512_sub_epi32(_mm512_maskz_loadu_epi32(valid, positions + i + 1), pos);
            const __mmask16 fast = _mm512_mask_cmplt_epu32_mask(valid, _mm512_sub_epi32(key, fast_lo), fast_size);
            // The lanes before the first one outside the fast range.
            const auto outside = static_cast<unsigned>(valid & ~fast);
            const __mmask16 use = outside == 0 ? valid : static_cast<__mmask16>((1u << __builtin_ctz(outside)) - 1);
            const __mmask16 odd = static_cast<__mmask16>(_mm512_test_epi32_mask(key, one) ^ flip);
            const __mmask16 by_parity[2] = {static_cast<__mmask16>(use & ~odd), static_cast<__mmask16>(use & odd)};
            for (int p = 0; p < 2; ++p) {
                const __mmask16 lt = _mm512_mask_cmplt_epu32_mask(by_parity[p], m, min_m[p]);
                min_m[p] = _mm512_mask_mov_epi32(min_m[p], lt, m);
                min_pos[p] = _mm512_mask_mov_epi32(min_pos[p], lt, pos);
                min_key[p] = _mm512_mask_mov_epi32(min_key[p], lt, key);
                const __mmask16 gt = _mm512_mask_cmpgt_epu32_mask(by_parity[p], m, max_m[p]);
                max_m[p] = _mm512_mask_mov_epi32(max_m[p], gt, m);
                max_pos[p] = _mm512_mask_mov_epi32(max_pos[p], gt, pos);
                max_key[p] = _mm512_mask_mov_epi32(max_key[p], gt, key);
            }
            lo = _mm512_mask_min_epu32(lo, use, lo, key);
            hi = _mm512_mask_max_epu32(hi, use, hi, key);
            sum = _mm512_mask_add_epi32(sum, use, sum, m);
            const __mmask16 ge = _mm512_mask_cmpge_epu32_mask(use, m, ceiling);
            sum_ge = _mm512_mask_add_epi32(sum_ge, ge, sum_ge, m);
            distinct += static_cast<uint64_t>(__builtin_popcount(use));
            n_ge += static_cast<uint64_t>(__builtin_popcount(ge));
            i += static_cast<std::size_t>(__builtin_popcount(use));
            if (use != valid) break;
        }
        for (int p = 0; p < 2; ++p) {
            _mm512_store_si512(s.min_m[p], min_m[p]);
            _mm512_store_si512(s.min_pos[p], min_pos[p]);
            _mm512_store_si512(s.min_key[p], min_key[p]);
            _mm512_store_si512(s.max_m[p], max_m[p]);
            _mm512_store_si512(s.max_pos[p], max_pos[p]);
            _mm512_store_si512(s.max_key[p], max_key[p]);
        }
        _mm512_store_si512(s.lo, lo);
        _mm512_store_si512(s.hi, hi);
        _mm512_store_si512(s.sum, sum);
        _mm512_store_si512(s.sum_ge, sum_ge);
        s.distinct += distinct;
        s.n_ge += n_ge;
        return i;
    }
#endif

    void enter_group(int g) {
        flush();
        group_ = g;
        // Fast range: the binade's floats inside [a,b), without its first one.
        const uint64_t lo = std::max<uint64_t>(group_key_lo(g) + 1, frame_.key_a);
        const uint64_t hi = std::min<uint64_t>(group_key_hi(g), frame_.key_b);
        fast_lo_ = static_cast<uint32_t>(lo);
        fast_size_ = hi > lo ? static_cast<uint32_t>(hi - lo) : 0;
        ceiling_ = frame_.ideal_ceiling[static_cast<std::size_t>(g)];
        parity_flip_ = g >= 256 ? 0u : 1u;  // a negative key is ~bits
    }

    void flush() {
        if (group_ < 0) return;
        const LaneState& s = lanes_;
        GroupCounts c;
        c.distinct = s.distinct;
        c.n_ge = s.n_ge;
        for (int l = 0; l < LaneState::kLanes; ++l) {
            c.inputs += s.sum[l];
            c.s_ge += s.sum_ge[l];
            c.lo_key = std::min(c.lo_key, s.lo[l]);
            c.hi_key = std::max(c.hi_key, s.hi[l]);
        }
        c.n_lt = c.distinct - c.n_ge;
        c.s_lt = c.inputs - c.s_ge;
        uint64_t* const mins[2] = {&c.min_even, &c.min_odd};
        uint64_t* const maxs[2] = {&c.max_even, &c.max_odd};
        for (int p = 0; p < 2; ++p) {
            // The first in input order among the lanes' extremes.
            int lmin = 0, lmax = 0;
            for (int l = 1; l < LaneState::kLanes; ++l) {
                if (s.min_m[p][l] < s.min_m[p][lmin] ||
                    (s.min_m[p][l] == s.min_m[p][lmin] && s.min_pos[p][l] < s.min_pos[p][lmin]))
                    lmin = l;
                if (s.max_m[p][l] > s.max_m[p][lmax] ||
                    (s.max_m[p][l] == s.max_m[p][lmax] && s.max_pos[p][l] < s.max_pos[p][lmax]))
                    lmax = l;
            }
            if (s.min_m[p][lmin] != std::numeric_limits<uint32_t>::max()) {
                *mins[p] = s.min_m[p][lmin];
                c.min_key[p] = s.min_key[p][lmin];
            }
            if (s.max_m[p][lmax] != 0) {
                *maxs[p] = s.max_m[p][lmax];
                c.max_key[p] = s.max_key[p][lmax];
            }
        }
        out_.group_inputs_all[static_cast<std::size_t>(group_)] += c.inputs;
        out_.groups[static_cast<std::size_t>(group_)].merge(c);
        lanes_.reset();
    }

    const SweepFrame& frame_;
    RunCounter& out_;
    const bool avx512_;
    LaneState lanes_;
    int group_ = -1;
    uint32_t fast_lo_ = 0, fast_size_ = 0, parity_flip_ = 0;
    uint64_t ceiling_ = 0;
    bool have_head_ = false;
};

}  // namespace

std::string BinadeCount::pattern() const {
    if (floats == 0 || distinct != floats) return {};
    const bool has_even = max_even > 0, has_odd = max_odd > 0;
    if (has_even && has_odd) {
        if (min_even != max_even || min_odd != max_odd) return {};
        if (min_even == min_odd) return std::to_string(min_even);
        return std::to_string(min_even) + "/" + std::to_string(min_odd);
    }
    if (has_even && min_even == max_even) return std::to_string(min_even);
    if (has_odd && min_odd == max_odd) return std::to_string(min_odd);
    return {};
}

uint64_t SweepSummary::outside_inputs_of(float x) const {
    for (const auto& v : outside_values)
        if (v.value == x || (std::isnan(v.value) && std::isnan(x))) return v.inputs;
    return 0;
}

const BinadeCount* SweepSummary::binade(int sign, int exponent) const {
    for (const auto& b : binades)
        if (b.sign == sign && b.exponent == exponent) return &b;
    return nullptr;
}

namespace {

// The summary: per binade, floats in the interval, never produced, deviation
// from the ideal; the outside outputs; the total variation distance.
SweepSummary summarize(const SweepFrame& frame, const RunCounter& total, uint64_t count) {
    SweepSummary s;
    s.inputs = count;
    // Per binade: floats in the interval, never produced, deviation from ideal.
    double abs_dev_total = 0.0;
    for (int g = 0; g < kGroups; ++g) {
        const uint64_t lo = std::max<uint64_t>(group_key_lo(g), frame.key_a);
        const uint64_t hi = std::min<uint64_t>(group_key_hi(g), frame.key_b);
        const GroupCounts& c = total.groups[static_cast<std::size_t>(g)];
        s.distinct_inside += c.distinct;
        if (lo >= hi) continue;
        if (c.distinct > 0) {
            if (s.distinct_inside == c.distinct) s.lowest_inside = key_float(c.lo_key);
            s.highest_inside = key_float(c.hi_key);
        }
        BinadeCount bc;
        bc.sign = g >= 256 ? 1 : -1;
        const int field = group_exponent_field(g);
        bc.exponent = field == 0 ? -127 : field - kFloatExponentBias;
        bc.first = key_float(static_cast<uint32_t>(lo));
        bc.last = key_float(static_cast<uint32_t>(hi - 1));
        bc.floats = hi - lo;
        bc.distinct = c.distinct;
        bc.inputs = c.inputs;
        bc.ideal = frame.ideal[static_cast<std::size_t>(g)];
        const bool has_even = c.max_even > 0, has_odd = c.max_odd > 0;
        bc.min_even = has_even ? c.min_even : 0;
        bc.max_even = c.max_even;
        bc.min_odd = has_odd ? c.min_odd : 0;
        bc.max_odd = c.max_odd;
        bc.edge_multiplicity = c.edge;
        // The extreme floats apart from the binade's first one (edge_multiplicity).
        const int most = c.max_odd > c.max_even || (c.max_odd == c.max_even && c.max_key[1] < c.max_key[0]);
        const int least = has_odd && (!has_even || c.min_odd < c.min_even ||
                                      (c.min_odd == c.min_even && c.min_key[1] < c.min_key[0]));
        if (has_even || has_odd) {
            bc.most_produced = key_float(c.max_key[most]);
            bc.most_multiplicity = most ? c.max_odd : c.max_even;
            bc.least_produced = key_float(c.min_key[least]);
            bc.least_multiplicity = least ? c.min_odd : c.min_even;
        }
        bc.max_multiplicity = std::max({c.max_even, c.max_odd, c.edge});
        const bool edge_inside = group_key_lo(g) >= frame.key_a;
        bc.min_multiplicity = c.distinct < bc.floats
                                  ? 0
                                  : std::min({c.min_even, c.min_odd,
                                              edge_inside ? c.edge : std::numeric_limits<uint64_t>::max()});
        const double ideal = bc.ideal;
        bc.abs_deviation = (static_cast<double>(c.s_ge) - static_cast<double>(c.n_ge) * ideal) +
                           (static_cast<double>(c.n_lt) * ideal - static_cast<double>(c.s_lt)) +
                           static_cast<double>(bc.floats - c.distinct) * ideal;
        abs_dev_total += bc.abs_deviation;
        s.floats_in_interval += bc.floats;
        s.never_produced += bc.floats - c.distinct;
        // Binades are visited in increasing order: negative groups run from the
        // largest magnitude (group 0) up to zero, then the positive ones.
        s.binades.push_back(bc);
    }
    s.outside_distinct = total.outside_distinct;
    s.outside_inputs = total.outside_inputs;
    s.distinct = s.distinct_inside + s.outside_distinct;
    for (const auto& [k, m] : total.outside) s.outside_values.push_back({key_float(k), m});
    s.tv_distance = 0.5 * (abs_dev_total + static_cast<double>(s.outside_inputs)) / static_cast<double>(count);
    return s;
}

// Each binade's ideal multiplicity for `count` inputs over [a,b).
SweepFrame make_frame(uint64_t count, float a, float b) {
    SweepFrame frame;
    frame.key_a = float_key(a);
    frame.key_b = float_key(b);
    const double width = static_cast<double>(b) - static_cast<double>(a);
    for (int g = 0; g < kGroups; ++g) {
        const double ideal = group_spacing(g) * static_cast<double>(count) / width;
        frame.ideal[static_cast<std::size_t>(g)] = ideal;
        frame.ideal_ceiling[static_cast<std::size_t>(g)] =
            ideal > 1e19 ? std::numeric_limits<uint64_t>::max() : static_cast<uint64_t>(std::ceil(ideal));
    }

    return frame;
}


// Pass 1: runs of equal outputs, chunk by chunk, then the runs that cross chunk
// borders in chunk order. Returns the steps down (0: the counts are exact). Once
// a chunk steps down, every count will be redone by the recount, which counts
// the steps itself: chunks that have not started yet are skipped (which ones
// depends on timing, so nothing of this pass is kept then), and the chunk that
// stepped stops there.
uint64_t count_runs(const FloatBlockFn& f, const FloatBordersFn& fused, uint64_t count,
                    const ParallelFor& parallel_for, bool avx512, RunCounter& total) {
    const SweepFrame& frame = *total.frame;
    const auto chunks = static_cast<std::size_t>(chunk_count(count));
    std::vector<ChunkEnds> ends(chunks);
    std::atomic<bool> stepped{false};
    // Counters that a chunk takes and gives back (as many as chunks run at
    // once), merged at the end: merging is order-free (sums, minima and maxima,
    // ties to the smaller key), so which chunks shared a counter does not show.
    std::mutex idle_mutex;
    std::vector<std::unique_ptr<RunCounter>> idle;
    parallel_for(chunks, [&](std::size_t c) {
        std::unique_ptr<RunCounter> local;
        {
            std::lock_guard lock(idle_mutex);
            if (!idle.empty()) {
                local = std::move(idle.back());
                idle.pop_back();
            }
        }
        if (!stepped.load(std::memory_order_relaxed)) {
            if (!local) local = std::make_unique<RunCounter>(frame);
            const uint64_t first = c * kChunkSize;
            ends[c] = ChunkScanner(frame, *local, avx512).scan(f, fused, first, std::min(kChunkSize, count - first));
            if (ends[c].steps_down > 0) stepped.store(true, std::memory_order_relaxed);
        }
        std::lock_guard lock(idle_mutex);
        if (local) idle.push_back(std::move(local));
    });
    if (stepped.load()) return 1;  // some chunk stepped down: every count will be redone
    for (const auto& local : idle) total.merge(*local);
    uint64_t steps_down = 0;
    bool have_carry = false;
    Run carry;
    for (const ChunkEnds& e : ends) {
        steps_down += e.steps_down;
        Run head = e.head;
        if (have_carry) {
            if (carry.key == head.key) {
                head.count += carry.count;
            } else {
                total.add(carry.key, carry.count);
                steps_down += head.key < carry.key;
            }
        }
        if (e.single) {
            carry = head;
        } else {
            total.add(head.key, head.count);
            carry = e.tail;
        }
        have_carry = true;
    }
    total.add(carry.key, carry.count);
    return steps_down;
}

// Where the outputs of f lie, for the recount's first window: the binades of f
// on 2^16 inputs, runs of 16 at 4096 points evenly spaced over [0, count) (all
// of them when there are fewer), so that a binade's share is known to about
// count / 4096 inputs even where f follows its input closely.
std::array<uint64_t, kGroups> sample_mass(const FloatBlockFn& f, uint64_t count) {
    constexpr uint64_t kPoints = 4096, kRun = 16;
    std::array<uint64_t, kGroups> mass{};
    float values[kRun];
    const auto add = [&](uint64_t first, std::size_t n) {
        f(first, n, values);
        for (std::size_t i = 0; i < n; ++i) ++mass[static_cast<std::size_t>(group_of(float_key(values[i])))];
    };
    if (count <= kPoints * kRun) {
        for (uint64_t first = 0; first < count; first += kRun)
            add(first, static_cast<std::size_t>(std::min(kRun, count - first)));
    } else {
        for (uint64_t p = 0; p < kPoints; ++p) add(p * (count / kPoints), kRun);
    }
    return mass;
}

}  // namespace

SweepSummary exhaustive_sweep(const FloatBlockFn& f, uint64_t count, float a, float b,
                              const ParallelFor& parallel_for, const SweepLimits& limits) {
    return exhaustive_sweep(f, FloatBordersFn{}, count, a, b, parallel_for, limits);
}

SweepSummary exhaustive_sweep(const FloatBlockFn& f, const FloatBordersFn& borders, uint64_t count, float a, float b,
                              const ParallelFor& parallel_for, const SweepLimits& limits) {
    if (!(std::isfinite(a) && std::isfinite(b) && a < b))
        throw std::invalid_argument("exhaustive_sweep: needs finite a < b");
    if (count == 0 || count > (uint64_t{1} << 32))
        throw std::invalid_argument("exhaustive_sweep: needs 1 <= count <= 2^32");

    using Clock = std::chrono::steady_clock;
    const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    const SweepFrame frame = make_frame(count, a, b);
    RunCounter total(frame);
    const auto start = Clock::now();
    static const bool avx512 = have_avx512();
    const uint64_t steps_down = count_runs(f, limits.portable ? FloatBordersFn{} : borders, count, parallel_for,
                                        avx512 && !limits.portable, total);
    const double runs_seconds = since(start);
    const auto recount_start = Clock::now();
    RecountTrace trace;
    if (steps_down > 0) {
        // Equal outputs may not be adjacent: recount exactly (with the steps down).
        total = RunCounter(frame);
        if (count <= limits.sort_limit) trace = recount_sorted(f, count, parallel_for, total);
        else trace = recount_windows(f, count, parallel_for, sample_mass(f, count), limits.window_binades, total);
    }
    SweepSummary s = summarize(frame, total, count);
    s.non_monotone_steps = trace.steps_down;
    s.exact_fallback = steps_down > 0;
    s.recount_passes = trace.passes;
    s.recount_seconds = steps_down > 0 ? since(recount_start) : 0.0;
    s.runs_seconds = runs_seconds;
    return s;
}

}  // namespace warpcheck::chi2
