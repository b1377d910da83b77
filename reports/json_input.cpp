// The inverse of json_report.cpp: the document's layout undone, the members
// read from the model's descriptions (reports/result_json.h).
#include "reports/json_input.h"

#include <string>

#include <fmt/format.h>

#include "reports/render.h"
#include "reports/result_json.h"

namespace warpcheck {
namespace {

using Reader = FieldReader<TextNumbers>;

const ResultJson& member(const ResultJson& object, const char* key) {
    const auto it = object.find(key);
    if (it == object.end()) throw ResultFormatError(fmt::format("{}: missing", key));
    return *it;
}

JsonResults read_document(const ResultJson& document) {
    const ResultJson& tool = member(document, "tool");
    if (!tool.is_object() || !tool.contains("name") || tool["name"] != "warpcheck")
        throw JsonInputError("not a warpcheck results file");
    const ResultJson& version = member(document, "schema_version");
    if (version != kJsonSchemaVersion)
        throw JsonInputError(fmt::format("schema_version {} (this warpcheck reads {})", version.dump(), kJsonSchemaVersion));
    // The run's tool_version is the document's tool.version.
    ResultJson info = member(document, "run");
    if (info.is_object()) info["tool_version"] = member(tool, "version");
    JsonResults out;
    Reader::read(info, out.run.info, JsonPlace{nullptr, "run"});
    Reader::read(member(document, "totals"), out.totals, JsonPlace{nullptr, "totals"});
    Reader::read(member(document, "results"), out.run.results, JsonPlace{nullptr, "results"});
    return out;
}

}  // namespace

JsonResults read_json_results(const std::string& text) {
    const ResultJson document = ResultJson::parse(text, nullptr, false);
    if (document.is_discarded() || !document.is_object()) throw JsonInputError("not a JSON document");
    try {
        return read_document(document);
    } catch (const ResultFormatError& e) {
        throw JsonInputError(fmt::format("not a warpcheck results file: {}", e.what()));
    }
}

RunResult parse_json_results(const std::string& text) { return read_json_results(text).run; }

}  // namespace warpcheck
