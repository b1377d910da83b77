// PCG32 (O'Neill 2014, PCG-XSH-RR with 64-bit state): small, fast, statistically
// strong, and with 2^63 selectable streams, so every (case, check) pair of a run
// gets its own independent stream without coordination between threads.
#pragma once

#include <cstddef>
#include <cstdint>

namespace warpcheck {

class Pcg32 {
public:
    static constexpr uint64_t kMultiplier = 0x5851f42d4c957f2dULL;
    static constexpr uint64_t kDefaultState = 0x853c49e6748fea9bULL;
    static constexpr uint64_t kDefaultStream = 0xda3e39cb94b95bdbULL;

    constexpr Pcg32() = default;
    constexpr Pcg32(uint64_t sequence_index, uint64_t seed) { set_sequence(sequence_index, seed); }

    /// Selects stream `sequence_index` (any 64-bit value; the top bit is ignored)
    /// and positions it by `seed`, following the reference initialisation.
    constexpr void set_sequence(uint64_t sequence_index, uint64_t seed) {
        state_ = 0;
        inc_ = (sequence_index << 1u) | 1u;
        next_u32();
        state_ += seed;
        next_u32();
    }

    constexpr uint32_t next_u32() {
        const uint64_t old = state_;
        state_ = old * kMultiplier + inc_;
        return output(old);
    }

    /// 64 random bits: the first 32-bit draw gives the high half.
    constexpr uint64_t next_u64() {
        const uint64_t hi = next_u32();
        return (hi << 32) | next_u32();
    }

    /// Writes n draws of next_u64 to out[0, n): the same values, and the same
    /// state after. Eight steps at a time are computed from one state
    /// (the state k steps on is A^k s + c (A^(k-1) + ... + 1)), so they do not
    /// wait on each other's multiply as next_u64's chain of steps does.
    constexpr void next_u64s(uint64_t* out, std::size_t n) {
        uint64_t mult[9] = {1}, plus[9] = {0};
        for (int k = 1; k <= 8; ++k) mult[k] = mult[k - 1] * kMultiplier, plus[k] = plus[k - 1] * kMultiplier + inc_;
        std::size_t i = 0;
        for (; i + 4 <= n; i += 4) {
            uint32_t r[8] = {};
            for (int k = 0; k < 8; ++k) r[k] = output(mult[k] * state_ + plus[k]);
            state_ = mult[8] * state_ + plus[8];
            for (int j = 0; j < 4; ++j) out[i + j] = (uint64_t{r[2 * j]} << 32) | r[2 * j + 1];
        }
        for (; i < n; ++i) out[i] = next_u64();
    }

    /// A float in [0,1) on the 2^-24 grid: every value is exact and equally
    /// likely, and 1 is never returned (unlike u32 * 2^-32, which rounds to 1).
    constexpr float next_float() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }

    /// A double in [0,1) on the 2^-53 grid.
    constexpr double next_double() { return static_cast<double>(next_u64() >> 11) * 0x1p-53; }

    /// The generator's state and increment (for copies stepped in lanes, sampling/lanes.h).
    constexpr uint64_t state() const { return state_; }
    constexpr uint64_t increment() const { return inc_; }

    /// Moves the stream by `delta` steps (negative: backwards, as unsigned
    /// wrap-around) in O(log delta), by composing the LCG step with itself.
    constexpr void advance(int64_t delta) {
        uint64_t cur_mult = kMultiplier, cur_plus = inc_, acc_mult = 1, acc_plus = 0;
        for (auto d = static_cast<uint64_t>(delta); d > 0; d >>= 1) {
            if (d & 1u) {
                acc_mult *= cur_mult;
                acc_plus = acc_plus * cur_mult + cur_plus;
            }
            cur_plus = (cur_mult + 1) * cur_plus;
            cur_mult *= cur_mult;
        }
        state_ = acc_mult * state_ + acc_plus;
    }

    friend constexpr bool operator==(const Pcg32&, const Pcg32&) = default;

private:
    /// PCG-XSH-RR's output of a state: its xorshifted high bits, rotated by its top 5 bits.
    static constexpr uint32_t output(uint64_t state) {
        const auto xorshifted = static_cast<uint32_t>(((state >> 18u) ^ state) >> 27u);
        const auto rot = static_cast<uint32_t>(state >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
    }

    uint64_t state_ = kDefaultState;
    uint64_t inc_ = kDefaultStream;
};

}  // namespace warpcheck
