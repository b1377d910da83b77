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

/// A JSON results document as read: the run, and the totals the document
/// states (which a reader that trusts nothing compares with the rows).
struct JsonResults {
    RunResult run;
    Totals totals;
};

/// The run a JSON results document holds, every figure as it was written
/// (decimal text that round-trips a double; "NaN" and the infinities as
/// strings). Throws JsonInputError saying what is wrong with a document that
/// is not JSON, not of schema_version 1, or lacks a field or has one of the
/// wrong type (naming it, e.g. "results[3].verdict").
JsonResults read_json_results(const std::string& text);

/// read_json_results(text).run.
RunResult parse_json_results(const std::string& text);

}  // namespace warpcheck
