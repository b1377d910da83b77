// The report formats as strings, before they are written to a file: the
// write_*_report functions of reports/outputs.h are these plus an atomic write.
// Useful for writing to stdout and for tests.
#pragma once

#include <string>

#include "reports/result.h"

namespace warpcheck {

/// The version of the JSON schema (reports/schema/warpcheck-results.schema.json):
/// it goes up when a field is removed or changes meaning; added fields keep it.
inline constexpr int kJsonSchemaVersion = 1;

/// The self-contained HTML page: summary, pass/fail table, details with plots.
std::string render_html(const RunResult& run);
/// The JSON document, compact (plots carry long arrays), ending in a newline.
std::string render_json(const RunResult& run);
/// The JUnit XML document.
std::string render_junit(const RunResult& run);

}  // namespace warpcheck
