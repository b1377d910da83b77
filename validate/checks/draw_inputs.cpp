#include <bit>

#include "validate/checks/check.h"

namespace warpcheck {

float uniform_float_from_bits(uint64_t w) {
    // The real number w * 2^-64 rounded down to a float: the 24 leading bits of
    // w, scaled. Every float x of [2^-40, 1) then comes out with probability
    // exactly its spacing next_float_up(x) - x, as if a uniform real were
    // rounded down; below 2^-40 the floats on the 2^-64 grid do. So inputs reach
    // every binade a 32-bit generator or a low-discrepancy sequence can feed a
    // warp (u = k 2^-32 included), not just the 2^-24 grid.
    if (w == 0) return 0.0f;
    const int msb = 63 - std::countl_zero(w);
    const uint64_t significand = msb >= 23 ? w >> (msb - 23) : w << (23 - msb);
    const auto exponent = static_cast<uint32_t>(msb - 64 + 127);  // 63..126: always a normal float
    return std::bit_cast<float>(exponent << 23 | (static_cast<uint32_t>(significand) & 0x7fffffu));
}

void draw_inputs(Pcg32& rng, InputKind kind, std::span<WarpInput> out) {
    switch (kind) {
        case InputKind::Uniform1D:
            for (auto& in : out) in = {{uniform_float_from_bits(rng.next_u64()), 0.0f}, 0};
            break;
        case InputKind::Uniform2D:
            for (auto& in : out) {
                const float u0 = uniform_float_from_bits(rng.next_u64());
                in = {{u0, uniform_float_from_bits(rng.next_u64())}, 0};
            }
            break;
        case InputKind::Uniform3D:
            for (auto& in : out) {
                const float u0 = uniform_float_from_bits(rng.next_u64());
                const float u1 = uniform_float_from_bits(rng.next_u64());
                in = {{u0, u1, uniform_float_from_bits(rng.next_u64())}, 0};
            }
            break;
        case InputKind::Bits32:
            for (auto& in : out) in = {{0.0f, 0.0f}, rng.next_u32()};
            break;
        case InputKind::Bits64:
            for (auto& in : out) in = {{0.0f, 0.0f}, rng.next_u64()};
            break;
    }
}

}  // namespace warpcheck
