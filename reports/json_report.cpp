// The JSON report: every result with every figure, plot and table, in the
// schema of reports/schema/warpcheck-results.schema.json (see reports/README.md).
#include <cmath>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "reports/atomic_file.h"
#include "reports/outputs.h"
#include "reports/render.h"

namespace warpcheck {
namespace {

using Json = nlohmann::ordered_json;

/// JSON has no NaN or infinity: those become the strings "NaN", "Infinity" and
/// "-Infinity", so that nothing is lost (a NaN figure is often the finding).
Json number(double v) {
    if (std::isnan(v)) return "NaN";
    if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
    return v;
}

Json optional_number(const std::optional<double>& v) { return v ? number(*v) : Json(nullptr); }

Json numbers(const std::vector<double>& values) {
    Json array = Json::array();
    for (double v : values) array.push_back(number(v));
    return array;
}

const char* verdict_name(Verdict v) {
    switch (v) {
        case Verdict::Pass: return "pass";
        case Verdict::Fail: return "fail";
        case Verdict::Error: return "error";
        case Verdict::NotApplicable: return "not_applicable";
    }
    return "error";
}

const char* kind_name(Plot::Kind k) {
    switch (k) {
        case Plot::Kind::Lines: return "lines";
        case Plot::Kind::Bars: return "bars";
        case Plot::Kind::Points: return "points";
        case Plot::Kind::Heatmaps: return "heatmaps";
    }
    return "lines";
}

const char* scale_name(Heatmap::ColorScale s) {
    switch (s) {
        case Heatmap::ColorScale::Auto: return "auto";
        case Heatmap::ColorScale::Sequential: return "sequential";
        case Heatmap::ColorScale::Diverging: return "diverging";
    }
    return "auto";
}

Json plot_json(const Plot& plot) {
    Json series = Json::array();
    for (const Series& s : plot.series) series.push_back({{"label", s.label}, {"x", numbers(s.x)}, {"y", numbers(s.y)}});
    Json heatmaps = Json::array();
    for (const Heatmap& h : plot.heatmaps)
        heatmaps.push_back({{"label", h.label},
                            {"rows", h.rows},
                            {"cols", h.cols},
                            {"x_min", number(h.x_min)},
                            {"x_max", number(h.x_max)},
                            {"y_min", number(h.y_min)},
                            {"y_max", number(h.y_max)},
                            {"color_scale", scale_name(h.color_scale)},
                            {"min_color_limit", number(h.min_color_limit)},
                            {"values", numbers(h.values)}});
    return {{"kind", kind_name(plot.kind)},     {"title", plot.title}, {"x_label", plot.x_label},
            {"y_label", plot.y_label},          {"log_x", plot.log_x}, {"log_y", plot.log_y},
            {"series", std::move(series)},      {"heatmaps", std::move(heatmaps)}};
}

Json result_json(const CheckResult& r) {
    Json figures = Json::object();
    for (const Figure& f : r.figures) figures[f.name] = number(f.value);
    Json plots = Json::array();
    for (const Plot& p : r.plots) plots.push_back(plot_json(p));
    Json tables = Json::array();
    for (const Table& t : r.tables) tables.push_back({{"title", t.title}, {"columns", t.columns}, {"rows", t.rows}});
    Json phases = Json::object();
    for (const PhaseTime& p : r.phases) phases[p.phase] = number(p.seconds);
    return {{"case", r.case_name},
            {"check", r.check_name},
            {"verdict", verdict_name(r.verdict)},
            {"summary", r.summary},
            {"message", r.message},
            {"p_value", optional_number(r.p_value)},
            {"level", optional_number(r.level)},
            {"figures", std::move(figures)},
            {"samples", r.samples},
            {"seconds", number(r.seconds)},
            {"phases", std::move(phases)},
            {"stream", {{"seed", r.stream_seed}, {"sequence", r.stream_sequence}}},
            {"rerun_command", r.rerun_command},
            {"plots", std::move(plots)},
            {"tables", std::move(tables)}};
}

}  // namespace

std::string render_json(const RunResult& run) {
    const RunInfo& info = run.info;
    Json results = Json::array();
    for (const CheckResult& r : run.results) results.push_back(result_json(r));
    Json document = {
        {"schema_version", kJsonSchemaVersion},
        {"tool", {{"name", "warpcheck"}, {"version", info.tool_version}}},
        {"run",
         {{"command_line", info.command_line},
          {"seed", info.seed},
          {"threads", info.threads},
          {"samples", info.samples},
          {"family_alpha", number(info.family_alpha)},
          {"per_test_alpha", number(info.per_test_alpha)},
          {"statistical_tests", info.statistical_tests},
          {"wall_seconds", number(info.wall_seconds)},
          {"compiler", info.compiler},
          {"machine", info.machine},
          {"started_at", info.started_at}}},
        {"totals",
         {{"checks", run.results.size()},
          {"passed", run.count(Verdict::Pass)},
          {"failed", run.count(Verdict::Fail)},
          {"errors", run.count(Verdict::Error)},
          {"not_applicable", run.count(Verdict::NotApplicable)}}},
        {"results", std::move(results)},
    };
    if (info.shard_count > 0)
        document["run"]["shard"] = {{"index", info.shard_index}, {"count", info.shard_count}, {"jobs", info.run_jobs}};
    // Invalid UTF-8 in a name or message becomes U+FFFD rather than an exception.
    return document.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n";
}

void write_json_report(const RunResult& run, const std::string& path) {
    write_file_atomically(path, render_json(run));
}

}  // namespace warpcheck
