// Registration-time validation of a warp case: a case declared inconsistently
// (a view outside the domain, a view of an input coordinate the warp does not
// have, a warp whose types disagree with its declared input or domain) is
// refused by Registry::add_case with a message naming the case, instead of
// failing later in a check with a confusing number.
#pragma once

#include <string>
#include <vector>

#include "validate/api/warp_case.h"

namespace warpcheck {

/// What is inconsistent in the case's declaration, one sentence each; empty
/// when nothing is.
std::vector<std::string> case_problems(const WarpCase& warp);

}  // namespace warpcheck
