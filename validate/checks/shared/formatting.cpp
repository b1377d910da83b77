#include "validate/checks/shared/formatting.h"

#include <fmt/format.h>

namespace warpcheck {

std::string format_input(const WarpInput& in, InputKind kind) {
    switch (kind) {
        case InputKind::Uniform1D: return fmt::format("{:.9g}", in.u[0]);
        case InputKind::Uniform2D: return fmt::format("({:.9g}, {:.9g})", in.u[0], in.u[1]);
        case InputKind::Uniform3D: return fmt::format("({:.9g}, {:.9g}, {:.9g})", in.u[0], in.u[1], in.u[2]);
        case InputKind::Bits32: return fmt::format("{:#010x}", in.bits);
        case InputKind::Bits64: return fmt::format("{:#018x}", in.bits);
    }
    return "?";
}

std::string format_output(const WarpOutput& x, int dimension) {
    switch (dimension) {
        case 1: return fmt::format("{:.9g}", x[0]);
        case 2: return fmt::format("({:.9g}, {:.9g})", x[0], x[1]);
        default: return fmt::format("({:.9g}, {:.9g}, {:.9g})", x[0], x[1], x[2]);
    }
}

}  // namespace warpcheck
