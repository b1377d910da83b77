// "repeatability" (warps, lights, MIS) and "bsdf_repeatability" (BSDFs and
// phase functions): the same inputs give the same outputs, bit for bit.
#pragma once

#include <memory>

#include "validate/checks/check.h"

namespace warpcheck {

std::unique_ptr<Check> make_repeatability_check();
std::unique_ptr<Check> make_bsdf_repeatability_check();

}  // namespace warpcheck
