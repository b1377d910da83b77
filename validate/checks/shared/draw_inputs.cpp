#include <algorithm>
#include <bit>
#include <cstddef>

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

namespace {

/// The uniform inputs of `dims` coordinates, each from one 64-bit draw in the
/// order next_u64 gives them, drawn a block at a time (Pcg32::next_u64s).
void draw_uniform(Pcg32& rng, int dims, std::span<WarpInput> out) {
    constexpr std::size_t kBlock = 256;  // inputs per block of draws: 6 KiB of draws at most, on the stack
    uint64_t draws[kBlock * 3];
    for (std::size_t first = 0; first < out.size(); first += kBlock) {
        const std::size_t n = std::min(kBlock, out.size() - first);
        rng.next_u64s(draws, n * static_cast<std::size_t>(dims));
        for (std::size_t i = 0; i < n; ++i) {
            const uint64_t* d = draws + i * static_cast<std::size_t>(dims);
            WarpInput& in = out[first + i];
            in = {{uniform_float_from_bits(d[0]), dims > 1 ? uniform_float_from_bits(d[1]) : 0.0f}, 0};
            if (dims > 2) in.u[2] = uniform_float_from_bits(d[2]);
        }
    }
}

}  // namespace

void draw_inputs(Pcg32& rng, InputKind kind, std::span<WarpInput> out) {
    switch (kind) {
        case InputKind::Uniform1D:
            return draw_uniform(rng, 1, out);
        case InputKind::Uniform2D:
            return draw_uniform(rng, 2, out);
        case InputKind::Uniform3D:
            return draw_uniform(rng, 3, out);
        case InputKind::Bits32:
            for (auto& in : out) in = {{0.0f, 0.0f}, rng.next_u32()};
            break;
        case InputKind::Bits64:
            for (auto& in : out) in = {{0.0f, 0.0f}, rng.next_u64()};
            break;
    }
}

}  // namespace warpcheck
