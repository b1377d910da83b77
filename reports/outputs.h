// Writers for the machine- and human-readable views of a run. Each writes its
// file atomically (a temporary file in the same folder, renamed into place), so
// a reader never sees half a file; each throws ReportError with a clear message
// when the path cannot be written.
#pragma once

#include <stdexcept>
#include <string>

#include "reports/result.h"

namespace warpcheck {

struct ReportError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Self-contained HTML (inline SVG plots, no external resources).
void write_html_report(const RunResult& run, const std::string& path);
/// JSON in the documented schema (see reports/README.md or the schema file), with a version field.
void write_json_report(const RunResult& run, const std::string& path);
/// JUnit XML: one testcase per (case, check) row.
void write_junit_report(const RunResult& run, const std::string& path);

}  // namespace warpcheck
