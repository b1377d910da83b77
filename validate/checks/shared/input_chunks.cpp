#include "validate/checks/shared/input_chunks.h"

#include <cmath>
#include <limits>

#include "sampling/float_bits.h"

namespace warpcheck {

std::vector<float> edge_values() {
    // 0, every power of two 2^-k of [0, 1) down to the smallest denormal 2^-149
    // with its float neighbours (so every binade is entered at both ends), the
    // largest float below 1, and the smallest step of a 32-bit generator 2^-32
    // (a power of two, so in the list already).
    std::vector<float> values = {0.0f};
    for (int k = 1; k <= 149; ++k) {
        const float p = std::ldexp(1.0f, -k);
        values.push_back(p);
        values.push_back(next_float_up(p));
        if (k < 149) values.push_back(next_float_down(p));  // below 2^-149 is 0, already listed
    }
    values.push_back(kOneMinusEpsilon);
    return values;
}

std::vector<WarpInput> edge_inputs(InputKind kind) {
    // The corners every 2D warp is tried at in both coordinates; the full edge
    // list runs along each coordinate with the other at one of these.
    static constexpr float kCorners[] = {0.0f, 0x1p-24f, 0.5f, kOneMinusEpsilon};
    std::vector<WarpInput> inputs;
    switch (kind) {
        case InputKind::Uniform1D:
            for (float a : edge_values()) inputs.push_back({{a, 0.0f}, 0});
            break;
        case InputKind::Uniform2D:
            for (float a : kCorners)
                for (float b : kCorners) inputs.push_back({{a, b}, 0});
            for (float a : edge_values())
                for (float b : kCorners) {
                    inputs.push_back({{a, b}, 0});
                    inputs.push_back({{b, a}, 0});
                }
            break;
        case InputKind::Uniform3D:
            // The corners in all three coordinates, and each edge value in one
            // coordinate with the other two at a pair of corners.
            for (float a : kCorners)
                for (float b : kCorners)
                    for (float c : kCorners) inputs.push_back({{a, b, c}, 0});
            for (float e : edge_values())
                for (float a : kCorners)
                    for (float b : kCorners) {
                        inputs.push_back({{e, a, b}, 0});
                        inputs.push_back({{a, e, b}, 0});
                        inputs.push_back({{a, b, e}, 0});
                    }
            break;
        case InputKind::Bits32: {
            constexpr uint64_t m = std::numeric_limits<uint32_t>::max();
            for (uint64_t b : {uint64_t{0}, uint64_t{1}, m / 2 + 1, m - 1, m}) inputs.push_back({{0.0f, 0.0f}, b});
            break;
        }
        case InputKind::Bits64: {
            constexpr uint64_t m = std::numeric_limits<uint64_t>::max();
            for (uint64_t b : {uint64_t{0}, uint64_t{1}, m / 2 + 1, m - 1, m}) inputs.push_back({{0.0f, 0.0f}, b});
            break;
        }
    }
    return inputs;
}

std::vector<WarpInput> pilot_inputs(const CheckContext& ctx, InputKind kind, std::size_t count) {
    std::vector<WarpInput> inputs(count);
    for (std::size_t first = 0, c = 0; first < count; first += kInputChunkSize, ++c) {
        Pcg32 rng = ctx.chunk_rng(kPilotChunkBase + c);
        draw_inputs(rng, kind, std::span<WarpInput>(inputs).subspan(first, std::min(kInputChunkSize, count - first)));
    }
    return inputs;
}

}  // namespace warpcheck
