// A job: one check on one warp case, the unit the runner selects, seeds,
// shards and hands to a thread or a worker process.
#pragma once

#include <string>

#include "validate/checks/check.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

struct Job {
    const WarpCase* warp = nullptr;
    const Check* check = nullptr;
    /// Non-empty: the check does not apply (Check::not_applicable_because); the
    /// job is not run and its row is NotApplicable with this reason.
    std::string not_applicable{};
};

}  // namespace warpcheck
