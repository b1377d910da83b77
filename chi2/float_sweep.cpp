#include "chi2/float_sweep.h"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#if defined(__x86_64__)
#include <immintrin.h>
#endif
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace warpcheck::chi2 {
namespace {

// IEEE-754 binary32 layout (chi2 includes nothing from sampling/).
constexpr uint32_t kFloatSignMask = 0x80000000u;
constexpr int kFloatExponentBias = 127;
inline uint32_t float_to_bits(float x) { return std::bit_cast<uint32_t>(x); }
inline float bits_to_float(uint32_t b) { return std::bit_cast<float>(b); }

constexpr uint64_t kChunkSize = uint64_t{1} << 22;  // inputs per chunk: fixed, so counts ignore threads
constexpr std::size_t kBlockSize = 1024;            // outputs evaluated per call of f
constexpr int kGroups = 512;                        // binades: 256 negative, 256 positive (by sign + exponent)
constexpr std::size_t kOutsideKept = 16;
constexpr uint32_t kNanKey = 0xffffffffu;

// Floats as keys whose unsigned order is the numeric order; -0 is +0, every NaN
// one key above +inf.
inline uint32_t float_key(float x) {
    const uint32_t bits = float_to_bits(x);
    if ((bits & 0x7fffffffu) > 0x7f800000u) return kNanKey;
    if (bits == kFloatSignMask) return 0x80000000u;
    return (bits & kFloatSignMask) ? ~bits : bits | kFloatSignMask;
}
inline float key_float(uint32_t key) {
    if (key == kNanKey) return std::numeric_limits<float>::quiet_NaN();
    return bits_to_float(key & kFloatSignMask ? key & ~kFloatSignMask : ~key);
}

// The binade of a key: positive floats by exponent field (groups 256..511),
// negative ones by the exponent field of the next float towards zero, so that a
// negative binade (magnitudes (2^e, 2^(e+1)]) has one spacing (groups 0..255).
inline int group_of(uint32_t key) {
    if (key & kFloatSignMask) return static_cast<int>(key >> 23);
    const uint32_t magnitude = 0x7fffffffu - key;  // >= 1: -0 was mapped to +0
    return 255 - static_cast<int>((magnitude - 1) >> 23);
}
inline int group_exponent_field(int g) { return g >= 256 ? g - 256 : 255 - g; }
// Keys of group g: [lo, hi).
inline uint64_t group_key_lo(int g) {
    if (g >= 256) return static_cast<uint64_t>(g) << 23;
    return 0x7fffffffull - (static_cast<uint64_t>(group_exponent_field(g)) + 1) * (1ull << 23);
}
inline uint64_t group_key_hi(int g) {
    if (g >= 256) return (static_cast<uint64_t>(g) + 1) << 23;
    return 0x7fffffffull - static_cast<uint64_t>(group_exponent_field(g)) * (1ull << 23);
}
inline double group_spacing(int g) { return std::ldexp(1.0, std::max(group_exponent_field(g), 1) - 150); }

struct GroupCounts {
    uint64_t distinct = 0, inputs = 0;
    uint64_t min_even = std::numeric_limits<uint64_t>::max(), max_even = 0;
    uint64_t min_odd = std::numeric_limits<uint64_t>::max(), max_odd = 0;
    uint64_t n_ge = 0, s_ge = 0, n_lt = 0, s_lt = 0;  // multiplicities >= / < the ideal: count and sum
    uint64_t edge = 0;  // multiplicity of the binade's first float (its power of two); not in min/max above
    // A key with each extreme above ([0] even, [1] odd): on ties the smaller
    // key, after the first in input order within a chunk, so that the merge
    // does not depend on which thread ran which chunk.
    uint32_t min_key[2] = {0, 0}, max_key[2] = {0, 0};
    // Smallest and largest key produced (the reach); lo > hi when none is.
    uint32_t lo_key = std::numeric_limits<uint32_t>::max(), hi_key = 0;

    void merge_keys(const GroupCounts& o) {
        const uint64_t mine_min[2] = {min_even, min_odd}, mine_max[2] = {max_even, max_odd};
        const uint64_t their_min[2] = {o.min_even, o.min_odd}, their_max[2] = {o.max_even, o.max_odd};
        for (int p = 0; p < 2; ++p) {
            if (their_min[p] < mine_min[p] || (their_min[p] == mine_min[p] && o.min_key[p] < min_key[p]))
                min_key[p] = o.min_key[p];
            if (their_max[p] > mine_max[p] || (their_max[p] == mine_max[p] && o.max_key[p] < max_key[p]))
                max_key[p] = o.max_key[p];
        }
    }

    void merge(const GroupCounts& o) {
        if (o.distinct > 0) {
            if (distinct == 0) {
                std::copy(o.min_key, o.min_key + 2, min_key);
                std::copy(o.max_key, o.max_key + 2, max_key);
            } else {
                merge_keys(o);
            }
        }
        edge = std::max(edge, o.edge);
        lo_key = std::min(lo_key, o.lo_key);
        hi_key = std::max(hi_key, o.hi_key);
        distinct += o.distinct;
        inputs += o.inputs;
        min_even = std::min(min_even, o.min_even);
        max_even = std::max(max_even, o.max_even);
        min_odd = std::min(min_odd, o.min_odd);
        max_odd = std::max(max_odd, o.max_odd);
        n_ge += o.n_ge;
        s_ge += o.s_ge;
        n_lt += o.n_lt;
        s_lt += o.s_lt;
    }
};

// What is fixed for a sweep: the interval's keys and each binade's ideal.
struct SweepFrame {
    uint32_t key_a = 0;
    uint64_t key_b = 0;  // exclusive; 64-bit so that it can be 2^32
    std::array<uint64_t, kGroups> ideal_ceiling{};  // multiplicity m counts as >= ideal iff m >= this
    std::array<double, kGroups> ideal{};
};

// Accumulates runs (key, multiplicity) of one chunk or of the whole sweep.
struct RunCounter {
    const SweepFrame* frame = nullptr;
    std::array<GroupCounts, kGroups> groups{};
    std::array<uint64_t, kGroups> group_inputs_all{};  // inputs per group, outside outputs included
    uint64_t outside_distinct = 0, outside_inputs = 0;
    std::vector<std::pair<uint32_t, uint64_t>> outside;  // smallest keys, sorted

    explicit RunCounter(const SweepFrame& f) : frame(&f) {}

    void add(uint32_t key, uint64_t m) {
        const int g = group_of(key);
        group_inputs_all[static_cast<std::size_t>(g)] += m;
        if (key >= frame->key_a && key < frame->key_b) {
            GroupCounts& c = groups[static_cast<std::size_t>(g)];
            c.lo_key = std::min(c.lo_key, key);
            c.hi_key = std::max(c.hi_key, key);
            ++c.distinct;
            c.inputs += m;
            // Significand parity: bits & 1, and a negative key is ~bits.
            const bool odd = ((key ^ (key >> 31)) & 1u) == 0;
            if (key == group_key_lo(g)) {
                c.edge = m;
            } else {
                GroupCounts one;
                one.distinct = 1;
                (odd ? one.min_odd : one.min_even) = m;
                (odd ? one.max_odd : one.max_even) = m;
                one.min_key[odd] = one.max_key[odd] = key;
                c.merge_keys(one);
                c.min_odd = std::min(c.min_odd, one.min_odd);
                c.max_odd = std::max(c.max_odd, one.max_odd);
                c.min_even = std::min(c.min_even, one.min_even);
                c.max_even = std::max(c.max_even, one.max_even);
            }
            if (m >= frame->ideal_ceiling[static_cast<std::size_t>(g)]) {
                ++c.n_ge;
                c.s_ge += m;
            } else {
                ++c.n_lt;
                c.s_lt += m;
            }
        } else {
            ++outside_distinct;
            outside_inputs += m;
            keep_outside(key, m);
        }
    }

    void keep_outside(uint32_t key, uint64_t m) {
        if (outside.size() == kOutsideKept && key >= outside.back().first) return;
        const auto pos = std::lower_bound(outside.begin(), outside.end(), std::make_pair(key, uint64_t{0}));
        outside.insert(pos, {key, m});
        if (outside.size() > kOutsideKept) outside.pop_back();
    }

    void merge(const RunCounter& o) {
        for (std::size_t g = 0; g < kGroups; ++g) {
            groups[g].merge(o.groups[g]);
            group_inputs_all[g] += o.group_inputs_all[g];
        }
        outside_distinct += o.outside_distinct;
        outside_inputs += o.outside_inputs;
        for (const auto& [k, m] : o.outside) keep_outside(k, m);
    }
};

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

// Converts a block of outputs to keys (vectorised by the compiler).
void to_keys(const float* x, std::size_t n, uint32_t* keys) {
    for (std::size_t i = 0; i < n; ++i) {
        uint32_t bits;
        std::memcpy(&bits, &x[i], sizeof bits);
        const uint32_t magnitude = bits & 0x7fffffffu;
        uint32_t k = (bits & kFloatSignMask) ? ~bits : bits | kFloatSignMask;
        k = magnitude == 0 ? 0x80000000u : k;
        k = magnitude > 0x7f800000u ? kNanKey : k;
        keys[i] = k;
    }
}

// Run borders of a block: writes the positions j in [0, n) where the bits of
// x[j] differ from those of x[j - 1] (x[-1] must be readable), in increasing
// order, and returns how many. positions needs n + 16 entries. Equal keys with
// different bits (-0 and +0, NaNs) are merged by the caller. n is a multiple
// of 16. One list per block, so the caller's loop over runs has no branch per
// 16 values.
std::size_t borders_portable(const float* x, std::size_t n, uint32_t* positions) {
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
        positions[count] = static_cast<uint32_t>(i);
        count += float_to_bits(x[i]) != float_to_bits(x[i - 1]);
    }
    return count;
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx512f"))) std::size_t borders_avx512(const float* x, std::size_t n, uint32_t* positions) {
    __m512i previous = _mm512_set1_epi32(static_cast<int>(float_to_bits(x[-1])));
    __m512i index = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512i sixteen = _mm512_set1_epi32(16);
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; i += 16) {
        const __m512i v = _mm512_loadu_si512(x + i);
        const __m512i before = _mm512_maskz_alignr_epi32(0xffff, v, previous, 15);  // [previous[15], v[0..14]]
        const __mmask16 m = _mm512_cmpneq_epu32_mask(v, before);
        // Compress in a register and store all 16 lanes: the store form of
        // vpcompressd is slow on some cores.
        _mm512_storeu_si512(positions + count, _mm512_maskz_compress_epi32(m, index));
        count += static_cast<std::size_t>(std::popcount(static_cast<unsigned>(m)));
        index = _mm512_add_epi32(index, sixteen);
        previous = v;
    }
    return count;
}
bool have_avx512() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f");
}
#endif

std::size_t borders(const float* x, std::size_t n, uint32_t* positions) {
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool avx512 = have_avx512();
    if (avx512) return borders_avx512(x, n, positions);
#endif
    return borders_portable(x, n, positions);
}

// Counts the runs of one chunk. The running binade's counters live in locals
// (a monotone sweep stays in one binade for millions of runs); the first float
// of a binade (a power of two, where the spacing changes) and every change of
// binade go through the slow path.
class ChunkScanner {
public:
    ChunkScanner(const SweepFrame& frame, RunCounter& out) : frame_(frame), out_(out) {}

    ChunkEnds scan(const FloatBlockFn& f, uint64_t first, uint64_t n) {
        // values[0] holds the last value of the previous block.
        std::vector<float> buffer(kBlockSize + 16 + 1);
        std::vector<uint32_t> positions(kBlockSize + 32);
        float* values = buffer.data() + 1;
        ChunkEnds ends;
        uint32_t run_key = 0;
        uint64_t run_start = 0;  // index in the chunk
        for (uint64_t done = 0; done < n;) {
            const auto len = static_cast<std::size_t>(std::min<uint64_t>(kBlockSize, n - done));
            f(first + done, len, values);
            const std::size_t padded = (len + 15) / 16 * 16;
            for (std::size_t i = len; i < padded; ++i) values[i] = values[len - 1];  // no borders in the padding
            if (done == 0) {
                values[-1] = values[0];
                run_key = float_key(values[0]);
            }
            const std::size_t borders_here = borders(values, padded, positions.data());
            for (std::size_t k = 0; k < borders_here; ++k) {
                const std::size_t j = positions[k];
                const uint32_t key = float_key(values[j]);
                if (key == run_key) continue;  // -0 after +0, or another NaN
                const uint64_t at = done + j;
                const uint64_t count = at - run_start;
                if (!have_head_) {
                    ends.head = Run{run_key, count};
                    have_head_ = true;
                } else {
                    add(run_key, count);
                }
                ends.steps_down += key < run_key;
                run_key = key;
                run_start = at;
            }
            values[-1] = values[len - 1];
            done += len;
        }
        flush();
        ends.tail = Run{run_key, n - run_start};
        if (!have_head_) {
            ends.head = ends.tail;
            ends.single = true;
        }
        return ends;
    }

private:
    void add(uint32_t key, uint64_t m) {
        if (key - fast_lo_ < fast_size_) {
            // Branch-free: parities and the side of the ideal alternate run by run.
            ++distinct_;
            inputs_ += m;
            lo_key_ = std::min(lo_key_, key);
            hi_key_ = std::max(hi_key_, key);
            const uint32_t odd = (key ^ parity_flip_) & 1u;
            // Rarely taken (a new extreme); the first in input order is kept.
            if (m < min_[odd]) {
                min_[odd] = m;
                min_key_[odd] = key;
            }
            if (m > max_[odd]) {
                max_[odd] = m;
                max_key_[odd] = key;
            }
            const uint64_t ge = m >= ceiling_ ? 1 : 0;
            n_ge_ += ge;
            s_ge_ += m & (0 - ge);
            s_all_ += m;
            return;
        }
        slow_add(key, m);
    }

    void slow_add(uint32_t key, uint64_t m) {
        const int g = group_of(key);
        if (g != group_) {
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
        if (key - fast_lo_ < fast_size_) return add(key, m);
        out_.add(key, m);  // the binade's first float, or outside [a,b)
    }

    void flush() {
        if (group_ < 0) return;
        GroupCounts c;
        c.distinct = distinct_;
        c.inputs = inputs_;
        c.min_even = min_[0];
        c.max_even = max_[0];
        c.min_odd = min_[1];
        c.max_odd = max_[1];
        std::copy(min_key_, min_key_ + 2, c.min_key);
        std::copy(max_key_, max_key_ + 2, c.max_key);
        c.n_ge = n_ge_;
        c.lo_key = lo_key_;
        c.hi_key = hi_key_;
        lo_key_ = std::numeric_limits<uint32_t>::max();
        hi_key_ = 0;
        c.s_ge = s_ge_;
        c.n_lt = distinct_ - n_ge_;
        c.s_lt = s_all_ - s_ge_;
        out_.group_inputs_all[static_cast<std::size_t>(group_)] += inputs_;
        out_.groups[static_cast<std::size_t>(group_)].merge(c);
        distinct_ = inputs_ = n_ge_ = s_ge_ = s_all_ = 0;
        min_[0] = min_[1] = std::numeric_limits<uint64_t>::max();
        max_[0] = max_[1] = 0;
    }

    const SweepFrame& frame_;
    RunCounter& out_;
    // The running binade's counters (see GroupCounts); [0] even, [1] odd.
    uint64_t distinct_ = 0, inputs_ = 0, n_ge_ = 0, s_ge_ = 0, s_all_ = 0;
    uint64_t min_[2] = {std::numeric_limits<uint64_t>::max(), std::numeric_limits<uint64_t>::max()};
    uint64_t max_[2] = {0, 0};
    uint32_t min_key_[2] = {0, 0}, max_key_[2] = {0, 0};
    uint32_t lo_key_ = std::numeric_limits<uint32_t>::max(), hi_key_ = 0;
    int group_ = -1;
    uint32_t fast_lo_ = 0, fast_size_ = 0, parity_flip_ = 0;
    uint64_t ceiling_ = 0;
    bool have_head_ = false;
};

// LSD radix sort of keys, 11 bits a pass.
void radix_sort(std::vector<uint32_t>& keys) {
    std::vector<uint32_t> tmp(keys.size());
    for (int shift = 0; shift < 32; shift += 11) {
        std::vector<std::size_t> count(2049, 0);
        for (uint32_t k : keys) ++count[((k >> shift) & 2047u) + 1];
        for (std::size_t i = 1; i < count.size(); ++i) count[i] += count[i - 1];
        for (uint32_t k : keys) tmp[count[(k >> shift) & 2047u]++] = k;
        keys.swap(tmp);
    }
}

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

uint64_t chunk_count(uint64_t count) { return (count + kChunkSize - 1) / kChunkSize; }

// Pass 1: runs of equal outputs, chunk by chunk, then the runs that cross chunk
// borders in chunk order. Returns the steps down (0: the counts are exact).
uint64_t count_runs(const FloatBlockFn& f, uint64_t count, const ParallelFor& parallel_for, RunCounter& total) {
    const SweepFrame& frame = *total.frame;
    const auto chunks = static_cast<std::size_t>(chunk_count(count));
    std::vector<ChunkEnds> ends(chunks);
    std::mutex total_mutex;
    parallel_for(chunks, [&](std::size_t c) {
        auto local = std::make_unique<RunCounter>(frame);
        const uint64_t first = c * kChunkSize;
        ends[c] = ChunkScanner(frame, *local).scan(f, first, std::min(kChunkSize, count - first));
        std::lock_guard lock(total_mutex);
        total.merge(*local);
    });
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

// Exact recount of a non-monotone f with at most SweepLimits::sort_limit inputs: sort all outputs.
void recount_sorted(const FloatBlockFn& f, uint64_t count, const ParallelFor& parallel_for, RunCounter& total) {
    const auto chunks = static_cast<std::size_t>(chunk_count(count));
    std::vector<uint32_t> keys(static_cast<std::size_t>(count));
    parallel_for(chunks, [&](std::size_t c) {
        const uint64_t first = c * kChunkSize;
        const uint64_t n = std::min(kChunkSize, count - first);
        std::vector<float> values(kBlockSize);
        for (uint64_t done = 0; done < n; done += kBlockSize) {
            const auto len = static_cast<std::size_t>(std::min<uint64_t>(kBlockSize, n - done));
            f(first + done, len, values.data());
            to_keys(values.data(), len, keys.data() + first + done);
        }
    });
    radix_sort(keys);
    std::size_t i = 0;
    while (i < keys.size()) {
        std::size_t j = i + 1;
        while (j < keys.size() && keys[j] == keys[i]) ++j;
        total.add(keys[i], j - i);
        i = j;
    }
}

// Keys of one block split by their slice of the window's counters (radix
// partitioning): slice s holds window indices [s, s + 1) * kSliceKeys.
constexpr std::size_t kSliceBits = 20;  // 2^20 counters (4 MiB) a slice
constexpr std::size_t kPartitionBlock = std::size_t{1} << 16;

struct WindowCounters {
    std::vector<uint32_t> counts;
    std::vector<std::mutex> slice_locks;
    std::array<int, kGroups> slot{};  // the group's place in the window, -1 if not in it
    explicit WindowCounters(std::size_t groups)
        : counts(groups << 23), slice_locks(std::max<std::size_t>(1, (groups << 23) >> kSliceBits)) {}
};

// Counts the keys of one chunk that fall in the window.
void count_chunk_in_window(const FloatBlockFn& f, uint64_t first, uint64_t n, WindowCounters& w) {
    const std::size_t slices = w.slice_locks.size();
    const std::size_t slice_shift = slices > 1 ? kSliceBits : 31;
    std::vector<float> values(kBlockSize);
    std::vector<uint32_t> keys(kBlockSize), index(kPartitionBlock), parted(kPartitionBlock);
    std::vector<uint32_t> offsets(slices + 1);
    for (uint64_t done = 0; done < n;) {
        std::size_t kept = 0;  // window indices of this partition block
        for (; kept + kBlockSize <= kPartitionBlock && done < n; done += kBlockSize) {
            const auto len = static_cast<std::size_t>(std::min<uint64_t>(kBlockSize, n - done));
            f(first + done, len, values.data());
            to_keys(values.data(), len, keys.data());
            for (std::size_t i = 0; i < len; ++i) {
                const int g = group_of(keys[i]);
                const int sl = w.slot[static_cast<std::size_t>(g)];
                index[kept] = (static_cast<uint32_t>(sl) << 23) + (keys[i] - static_cast<uint32_t>(group_key_lo(g)));
                kept += sl >= 0;
            }
        }
        std::fill(offsets.begin(), offsets.end(), 0u);
        for (std::size_t i = 0; i < kept; ++i) ++offsets[(index[i] >> slice_shift) + 1];
        for (std::size_t s = 1; s <= slices; ++s) offsets[s] += offsets[s - 1];
        std::vector<uint32_t> fill(offsets.begin(), offsets.end() - 1);
        for (std::size_t i = 0; i < kept; ++i) parted[fill[index[i] >> slice_shift]++] = index[i];
        for (std::size_t s = 0; s < slices; ++s) {
            if (offsets[s] == offsets[s + 1]) continue;
            std::lock_guard lock(w.slice_locks[s]);
            for (uint32_t i = offsets[s]; i < offsets[s + 1]; ++i) ++w.counts[parted[i]];
        }
    }
}

// Exact recount of a non-monotone f: counting passes over windows of the
// binades it touched (see the header for the method and its memory bound).
void recount_windows(const FloatBlockFn& f, uint64_t count, const ParallelFor& parallel_for,
                     const std::array<uint64_t, kGroups>& touched, int window_binades, RunCounter& total) {
    const auto chunks = static_cast<std::size_t>(chunk_count(count));
    std::vector<int> touched_groups;
    for (int g = 0; g < kGroups; ++g)
        if (touched[static_cast<std::size_t>(g)] > 0) touched_groups.push_back(g);
    const auto per_window = static_cast<std::size_t>(std::max(window_binades, 1));
    WindowCounters w(std::min(per_window, touched_groups.size()));
    for (std::size_t first_group = 0; first_group < touched_groups.size(); first_group += per_window) {
        const std::size_t groups_here = std::min(per_window, touched_groups.size() - first_group);
        w.slot.fill(-1);
        for (std::size_t k = 0; k < groups_here; ++k)
            w.slot[static_cast<std::size_t>(touched_groups[first_group + k])] = static_cast<int>(k);
        std::fill(w.counts.begin(), w.counts.end(), 0u);
        parallel_for(chunks, [&](std::size_t c) {
            const uint64_t first = c * kChunkSize;
            count_chunk_in_window(f, first, std::min(kChunkSize, count - first), w);
        });
        // A non-monotone f has two outputs at least, so no count reaches 2^32.
        for (std::size_t k = 0; k < groups_here; ++k) {
            const int g = touched_groups[first_group + k];
            const auto lo = static_cast<uint32_t>(group_key_lo(g));
            const uint64_t size = group_key_hi(g) - group_key_lo(g);
            for (uint64_t i = 0; i < size; ++i) {
                const uint32_t m = w.counts[(k << 23) + i];
                if (m != 0) total.add(lo + static_cast<uint32_t>(i), m);
            }
        }
    }
}

}  // namespace

SweepSummary exhaustive_sweep(const FloatBlockFn& f, uint64_t count, float a, float b,
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
    const uint64_t steps_down = count_runs(f, count, parallel_for, total);
    const double runs_seconds = since(start);
    const auto recount_start = Clock::now();
    if (steps_down > 0) {
        // Equal outputs may not be adjacent: recount exactly.
        const std::array<uint64_t, kGroups> touched = total.group_inputs_all;
        total = RunCounter(frame);
        if (count <= limits.sort_limit) recount_sorted(f, count, parallel_for, total);
        else recount_windows(f, count, parallel_for, touched, limits.window_binades, total);
    }
    SweepSummary s = summarize(frame, total, count);
    s.non_monotone_steps = steps_down;
    s.exact_fallback = steps_down > 0;
    s.recount_seconds = steps_down > 0 ? since(recount_start) : 0.0;
    s.runs_seconds = runs_seconds;
    return s;
}

}  // namespace warpcheck::chi2
