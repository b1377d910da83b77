// Placeholder until the report writers land: asking for a report is an error,
// never a silently missing file.
#include "reports/outputs.h"

namespace warpcheck {

void write_html_report(const RunResult&, const std::string& path) {
    throw ReportError("cannot write " + path + ": the HTML report is not implemented yet");
}
void write_json_report(const RunResult&, const std::string& path) {
    throw ReportError("cannot write " + path + ": the JSON report is not implemented yet");
}
void write_junit_report(const RunResult&, const std::string& path) {
    throw ReportError("cannot write " + path + ": the JUnit report is not implemented yet");
}

}  // namespace warpcheck
