#include "validate/checks/input_chunks.h"

#include <limits>

#include "sampling/float_bits.h"

namespace warpcheck {

std::vector<WarpInput> edge_inputs(InputKind kind) {
    static constexpr float kEdges[] = {0.0f, 0x1p-24f, 0.5f, kOneMinusEpsilon};
    std::vector<WarpInput> inputs;
    switch (kind) {
        case InputKind::Uniform1D:
            for (float a : kEdges) inputs.push_back({{a, 0.0f}, 0});
            break;
        case InputKind::Uniform2D:
            for (float a : kEdges)
                for (float b : kEdges) inputs.push_back({{a, b}, 0});
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

}  // namespace warpcheck
