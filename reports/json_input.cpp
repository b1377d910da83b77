// The inverse of json_report.cpp: the same names, read in the same order.
#include "reports/json_input.h"

#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "reports/render.h"

namespace warpcheck {
namespace {

using Json = nlohmann::ordered_json;

double number(const Json& j) {
    if (j.is_number()) return j.get<double>();
    const std::string text = j.get<std::string>();
    if (text == "NaN") return std::numeric_limits<double>::quiet_NaN();
    if (text == "Infinity") return std::numeric_limits<double>::infinity();
    if (text == "-Infinity") return -std::numeric_limits<double>::infinity();
    throw JsonInputError(fmt::format("'{}' is not a number", text));
}

std::optional<double> optional_number(const Json& j) {
    return j.is_null() ? std::nullopt : std::optional<double>(number(j));
}

std::vector<double> numbers(const Json& j) {
    std::vector<double> v;
    v.reserve(j.size());
    for (const Json& x : j) v.push_back(number(x));
    return v;
}

template <typename Enum, std::size_t N>
Enum named(const Json& j, const char* const (&names)[N], const char* what) {
    const std::string text = j.get<std::string>();
    for (std::size_t i = 0; i < N; ++i)
        if (text == names[i]) return static_cast<Enum>(i);
    throw JsonInputError(fmt::format("'{}' is not a {}", text, what));
}

// In the order of the enumerators, as json_report.cpp names them.
const char* const kVerdicts[] = {"pass", "fail", "error"};
const char* const kPlotKinds[] = {"lines", "bars", "points", "heatmaps"};
const char* const kColorScales[] = {"auto", "sequential", "diverging"};

Heatmap heatmap(const Json& j) {
    Heatmap h;
    h.label = j.at("label").get<std::string>();
    h.rows = j.at("rows").get<int>();
    h.cols = j.at("cols").get<int>();
    h.x_min = number(j.at("x_min")), h.x_max = number(j.at("x_max"));
    h.y_min = number(j.at("y_min")), h.y_max = number(j.at("y_max"));
    h.color_scale = named<Heatmap::ColorScale>(j.at("color_scale"), kColorScales, "colour scale");
    h.min_color_limit = number(j.at("min_color_limit"));
    h.values = numbers(j.at("values"));
    return h;
}

Plot plot(const Json& j) {
    Plot p;
    p.kind = named<Plot::Kind>(j.at("kind"), kPlotKinds, "plot kind");
    p.title = j.at("title").get<std::string>();
    p.x_label = j.at("x_label").get<std::string>();
    p.y_label = j.at("y_label").get<std::string>();
    p.log_x = j.at("log_x").get<bool>();
    p.log_y = j.at("log_y").get<bool>();
    for (const Json& s : j.at("series"))
        p.series.push_back({s.at("label").get<std::string>(), numbers(s.at("x")), numbers(s.at("y"))});
    for (const Json& h : j.at("heatmaps")) p.heatmaps.push_back(heatmap(h));
    return p;
}

CheckResult result(const Json& j) {
    CheckResult r;
    r.case_name = j.at("case").get<std::string>();
    r.check_name = j.at("check").get<std::string>();
    r.verdict = named<Verdict>(j.at("verdict"), kVerdicts, "verdict");
    r.summary = j.at("summary").get<std::string>();
    r.message = j.at("message").get<std::string>();
    r.p_value = optional_number(j.at("p_value"));
    r.level = optional_number(j.at("level"));
    for (const auto& [name, value] : j.at("figures").items()) r.figures.push_back({name, number(value)});
    r.samples = j.at("samples").get<uint64_t>();
    r.seconds = number(j.at("seconds"));
    r.stream_seed = j.at("stream").at("seed").get<uint64_t>();
    r.stream_sequence = j.at("stream").at("sequence").get<uint64_t>();
    r.rerun_command = j.at("rerun_command").get<std::string>();
    for (const Json& p : j.at("plots")) r.plots.push_back(plot(p));
    for (const Json& t : j.at("tables"))
        r.tables.push_back({t.at("title").get<std::string>(), t.at("columns").get<std::vector<std::string>>(),
                            t.at("rows").get<std::vector<std::vector<std::string>>>()});
    return r;
}

RunInfo run_info(const Json& document) {
    RunInfo info;
    const Json& run = document.at("run");
    info.tool_version = document.at("tool").at("version").get<std::string>();
    info.command_line = run.at("command_line").get<std::string>();
    info.seed = run.at("seed").get<uint64_t>();
    info.threads = run.at("threads").get<unsigned>();
    info.samples = run.at("samples").get<uint64_t>();
    info.family_alpha = number(run.at("family_alpha"));
    info.per_test_alpha = number(run.at("per_test_alpha"));
    info.statistical_tests = run.at("statistical_tests").get<int>();
    info.wall_seconds = number(run.at("wall_seconds"));
    info.compiler = run.at("compiler").get<std::string>();
    info.machine = run.at("machine").get<std::string>();
    info.started_at = run.at("started_at").get<std::string>();
    if (run.contains("shard")) {
        info.shard_index = run.at("shard").at("index").get<unsigned>();
        info.shard_count = run.at("shard").at("count").get<unsigned>();
        info.run_jobs = run.at("shard").at("jobs").get<uint64_t>();
    }
    return info;
}

}  // namespace

RunResult parse_json_results(const std::string& text) {
    const Json document = Json::parse(text, nullptr, false);
    if (document.is_discarded() || !document.is_object()) throw JsonInputError("not a JSON document");
    try {
        if (document.at("tool").at("name") != "warpcheck") throw JsonInputError("not a warpcheck results file");
        const int version = document.at("schema_version").get<int>();
        if (version != kJsonSchemaVersion)
            throw JsonInputError(fmt::format("schema_version {} (this warpcheck reads {})", version, kJsonSchemaVersion));
        RunResult run;
        run.info = run_info(document);
        for (const Json& r : document.at("results")) run.results.push_back(result(r));
        return run;
    } catch (const nlohmann::json::exception& e) {
        throw JsonInputError(fmt::format("not a warpcheck results file: {}", e.what()));
    }
}

}  // namespace warpcheck
