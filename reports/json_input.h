// Reading back a JSON results document (reports/schema), as `validate --json`
// wrote it: how `validate --merge` combines the shards of a run.
#pragma once

#include <stdexcept>
#include <string>

#include "reports/result.h"

namespace warpcheck {

struct JsonInputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The run a JSON results document holds, every figure as it was written
/// (decimal text that round-trips a double; "NaN" and the infinities as
/// strings). Throws JsonInputError saying what is wrong with a document that
/// is not JSON, not of schema_version 1, or lacks a field.
RunResult parse_json_results(const std::string& text);

}  // namespace warpcheck
