// A CheckResult as bytes and back, complete and exact: how an isolated worker
// process hands its result to the runner. Every field travels; doubles keep
// their bit patterns (NaN payloads, infinities, -0), so a result read back is
// the result written, and isolated runs print the figures in-process runs do.
#pragma once

#include <optional>
#include <string>

#include "reports/result.h"

namespace warpcheck {

std::string encode_result(const CheckResult& result);

/// The result encoded in `bytes`, or nullopt if they are not a whole encoding
/// (a worker that died while writing).
std::optional<CheckResult> decode_result(const std::string& bytes);

}  // namespace warpcheck
