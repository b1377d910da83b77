#include "validate/result_codec.h"

#include <bit>
#include <cstdint>

#include <nlohmann/json.hpp>

namespace warpcheck {
namespace {

using nlohmann::json;

// A double as the integer of its bit pattern: JSON numbers cannot hold NaN or
// infinity, and decimal text need not round-trip a NaN payload.
json bits(double v) { return std::bit_cast<uint64_t>(v); }
double from_bits(const json& j) { return std::bit_cast<double>(j.get<uint64_t>()); }

json doubles(const std::vector<double>& v) {
    json a = json::array();
    for (double d : v) a.push_back(bits(d));
    return a;
}
std::vector<double> doubles_from(const json& j) {
    std::vector<double> v;
    v.reserve(j.size());
    for (const auto& d : j) v.push_back(from_bits(d));
    return v;
}
json optional_double(const std::optional<double>& v) { return v ? bits(*v) : json(nullptr); }
std::optional<double> optional_from(const json& j) {
    return j.is_null() ? std::nullopt : std::optional<double>(from_bits(j));
}

json encode_heatmap(const Heatmap& h) {
    return {{"label", h.label},         {"rows", h.rows},
            {"cols", h.cols},           {"range", doubles({h.x_min, h.x_max, h.y_min, h.y_max})},
            {"values", doubles(h.values)}, {"scale", static_cast<int>(h.color_scale)},
            {"min_limit", bits(h.min_color_limit)}};
}
Heatmap decode_heatmap(const json& j) {
    Heatmap h;
    h.label = j.at("label").get<std::string>();
    h.rows = j.at("rows").get<int>();
    h.cols = j.at("cols").get<int>();
    const auto range = doubles_from(j.at("range"));
    h.x_min = range.at(0), h.x_max = range.at(1), h.y_min = range.at(2), h.y_max = range.at(3);
    h.values = doubles_from(j.at("values"));
    h.color_scale = static_cast<Heatmap::ColorScale>(j.at("scale").get<int>());
    h.min_color_limit = from_bits(j.at("min_limit"));
    return h;
}

json encode_plot(const Plot& p) {
    json series = json::array(), heatmaps = json::array();
    for (const auto& s : p.series) series.push_back({{"label", s.label}, {"x", doubles(s.x)}, {"y", doubles(s.y)}});
    for (const auto& h : p.heatmaps) heatmaps.push_back(encode_heatmap(h));
    return {{"kind", static_cast<int>(p.kind)}, {"title", p.title}, {"x_label", p.x_label},
            {"y_label", p.y_label},             {"log_x", p.log_x}, {"log_y", p.log_y},
            {"series", series},                 {"heatmaps", heatmaps}};
}
Plot decode_plot(const json& j) {
    Plot p;
    p.kind = static_cast<Plot::Kind>(j.at("kind").get<int>());
    p.title = j.at("title").get<std::string>();
    p.x_label = j.at("x_label").get<std::string>();
    p.y_label = j.at("y_label").get<std::string>();
    p.log_x = j.at("log_x").get<bool>();
    p.log_y = j.at("log_y").get<bool>();
    for (const auto& s : j.at("series"))
        p.series.push_back({s.at("label").get<std::string>(), doubles_from(s.at("x")), doubles_from(s.at("y"))});
    for (const auto& h : j.at("heatmaps")) p.heatmaps.push_back(decode_heatmap(h));
    return p;
}

}  // namespace

std::string encode_result(const CheckResult& r) {
    json figures = json::array(), plots = json::array(), tables = json::array();
    for (const auto& f : r.figures) figures.push_back({f.name, bits(f.value)});
    for (const auto& p : r.plots) plots.push_back(encode_plot(p));
    for (const auto& t : r.tables) tables.push_back({{"title", t.title}, {"columns", t.columns}, {"rows", t.rows}});
    json phases = json::array();
    for (const auto& p : r.phases) phases.push_back({p.phase, bits(p.seconds)});
    const json j = {{"case", r.case_name},      {"check", r.check_name},
                    {"verdict", static_cast<int>(r.verdict)},
                    {"summary", r.summary},     {"message", r.message},
                    {"figures", figures},       {"p_value", optional_double(r.p_value)},
                    {"level", optional_double(r.level)},
                    {"plots", plots},           {"tables", tables},
                    {"stream_seed", r.stream_seed}, {"stream_sequence", r.stream_sequence},
                    {"samples", r.samples},     {"seconds", bits(r.seconds)}, {"phases", phases},
                    {"rerun", r.rerun_command}};
    // CBOR: compact, and strings from a warp's messages need not be valid UTF-8.
    const std::vector<uint8_t> bytes = json::to_cbor(j);
    return std::string(bytes.begin(), bytes.end());
}

std::optional<CheckResult> decode_result(const std::string& bytes) {
    const json j = json::from_cbor(bytes, true, false);
    if (j.is_discarded()) return std::nullopt;
    try {
        CheckResult r;
        r.case_name = j.at("case").get<std::string>();
        r.check_name = j.at("check").get<std::string>();
        r.verdict = static_cast<Verdict>(j.at("verdict").get<int>());
        r.summary = j.at("summary").get<std::string>();
        r.message = j.at("message").get<std::string>();
        for (const auto& f : j.at("figures")) r.figures.push_back({f.at(0).get<std::string>(), from_bits(f.at(1))});
        r.p_value = optional_from(j.at("p_value"));
        r.level = optional_from(j.at("level"));
        for (const auto& p : j.at("plots")) r.plots.push_back(decode_plot(p));
        for (const auto& t : j.at("tables"))
            r.tables.push_back({t.at("title").get<std::string>(), t.at("columns").get<std::vector<std::string>>(),
                                t.at("rows").get<std::vector<std::vector<std::string>>>()});
        r.stream_seed = j.at("stream_seed").get<uint64_t>();
        r.stream_sequence = j.at("stream_sequence").get<uint64_t>();
        r.samples = j.at("samples").get<uint64_t>();
        r.seconds = from_bits(j.at("seconds"));
        for (const auto& p : j.at("phases")) r.phases.push_back({p.at(0).get<std::string>(), from_bits(p.at(1))});
        r.rerun_command = j.at("rerun").get<std::string>();
        return r;
    } catch (const nlohmann::json::exception&) {
        return std::nullopt;
    }
}

}  // namespace warpcheck
