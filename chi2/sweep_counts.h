// The counting model of the exhaustive float sweep (chi2/float_sweep.h), shared
// by its run scan (float_sweep.cpp) and its exact recount of non-monotone
// functions (sweep_recount.cpp): floats as ordered keys, binades as groups, and
// the counts kept per binade. Internal to chi2: nothing outside includes it.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

namespace warpcheck::chi2::sweep {

// IEEE-754 binary32 layout (chi2 includes nothing from sampling/).
inline constexpr uint32_t kFloatSignMask = 0x80000000u;
inline constexpr int kFloatExponentBias = 127;
inline uint32_t float_to_bits(float x) { return std::bit_cast<uint32_t>(x); }
inline float bits_to_float(uint32_t b) { return std::bit_cast<float>(b); }

inline constexpr uint64_t kChunkSize = uint64_t{1} << 22;  // inputs per chunk: fixed, so counts ignore threads
inline constexpr std::size_t kBlockSize = 4096;            // outputs evaluated per call of f
inline constexpr int kGroups = 512;                        // binades: 256 negative, 256 positive (by sign + exponent)
inline constexpr std::size_t kOutsideKept = 16;
inline constexpr uint32_t kNanKey = 0xffffffffu;

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

inline uint64_t chunk_count(uint64_t count) { return (count + kChunkSize - 1) / kChunkSize; }

// Converts a block of outputs to keys (vectorised by the compiler).
inline void to_keys(const float* x, std::size_t n, uint32_t* keys) {
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

}  // namespace warpcheck::chi2::sweep
