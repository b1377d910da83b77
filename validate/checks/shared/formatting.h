// Text for inputs and outputs in result tables and messages.
#pragma once

#include <string>

#include "validate/api/warp_case.h"

namespace warpcheck {

/// "(0.5, 0.25)" for uniform inputs (9 significant digits, enough to read back a
/// float), "0x00000000ffffffff" for raw bits.
std::string format_input(const WarpInput& in, InputKind kind);
/// "(x, y, z)" with as many coordinates as the domain's points have.
std::string format_output(const WarpOutput& x, int dimension);

}  // namespace warpcheck
