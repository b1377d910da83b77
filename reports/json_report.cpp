// The JSON report: every result with every figure, plot and table, in the
// schema of reports/schema/warpcheck-results.schema.json (see reports/README.md).
// The members come from the model's descriptions (reports/result_json.h); this
// file only lays out the document around them.
#include <string>

#include "reports/atomic_file.h"
#include "reports/outputs.h"
#include "reports/render.h"
#include "reports/result_json.h"

namespace warpcheck {

std::string render_json(const RunResult& run) {
    using Writer = FieldWriter<TextNumbers>;
    ResultJson info = Writer::write(run.info);
    ResultJson document = ResultJson::object();
    document["schema_version"] = kJsonSchemaVersion;
    document["tool"] = {{"name", "warpcheck"}, {"version", info.at("tool_version")}};
    info.erase("tool_version");
    document["run"] = std::move(info);
    document["totals"] = Writer::write(run.totals());
    document["results"] = Writer::write(run.results);
    // Invalid UTF-8 in a name or message becomes U+FFFD rather than an exception.
    return document.dump(-1, ' ', false, ResultJson::error_handler_t::replace) + "\n";
}

void write_json_report(const RunResult& run, const std::string& path) {
    write_file_atomically(path, render_json(run));
}

}  // namespace warpcheck
