#include "validate/check.h"

namespace warpcheck {

void draw_inputs(Pcg32& rng, InputKind kind, std::span<WarpInput> out) {
    switch (kind) {
        case InputKind::Uniform1D:
            for (auto& in : out) in = {{rng.next_float(), 0.0f}, 0};
            break;
        case InputKind::Uniform2D:
            for (auto& in : out) {
                const float u0 = rng.next_float();
                in = {{u0, rng.next_float()}, 0};
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
