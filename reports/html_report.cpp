// The HTML report: one self-contained page (inline CSS and SVG, no network, no
// script needed) that shows a run at a glance and the evidence of every check.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "reports/atomic_file.h"
#include "reports/outputs.h"
#include "reports/render.h"
#include "reports/svg_plot.h"
#include "reports/text.h"

namespace warpcheck {
namespace {

// The style sheet. Colours: red for failures, amber for errors, green for passes;
// everything else quiet greys, so that the verdicts carry the page.
constexpr const char* kStyle = R"CSS(
:root { --fail: #c62828; --fail-bg: #fdecea; --error: #b26a00; --error-bg: #fff4e0; --pass: #2e7d32; --pass-bg: #eaf5eb;
  --ink: #1f2328; --muted: #5f6773; --line: #d8dce1; --soft: #f5f6f8; --link: #1a5fb4; color-scheme: light; }
* { box-sizing: border-box; }
html { -webkit-text-size-adjust: 100%; }
body { margin: 0; color: var(--ink); background: #fff; line-height: 1.45;
  font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, "Noto Sans", "DejaVu Sans", "Liberation Sans", Arial, sans-serif; }
code, pre, .mono { font-family: ui-monospace, "SFMono-Regular", "DejaVu Sans Mono", "Liberation Mono", Menlo, Consolas, monospace; font-size: 12.5px; }
a { color: var(--link); text-decoration: none; } a:hover { text-decoration: underline; }
main, .banner-inner, footer { max-width: 1280px; margin: 0 auto; padding: 0 24px; }
.banner { color: #fff; background: var(--pass); padding: 18px 0 16px; }
.banner.fail { background: var(--fail); } .banner.error { background: var(--error); } .banner.empty { background: #59616b; }
.banner h1 { margin: 0; font-size: 24px; letter-spacing: 0.01em; }
.banner h1 .tool { font-weight: 400; opacity: 0.85; margin-right: 10px; }
.banner p { margin: 4px 0 0; opacity: 0.95; }
h2 { font-size: 18px; margin: 28px 0 12px; padding-bottom: 6px; border-bottom: 1px solid var(--line); }
.tiles { display: flex; flex-wrap: wrap; gap: 12px; margin: 20px 0 16px; }
.tile { flex: 1 1 140px; border: 1px solid var(--line); border-radius: 8px; padding: 10px 14px; background: var(--soft); }
.tile .n { display: block; font-size: 28px; font-weight: 700; line-height: 1.15; font-variant-numeric: tabular-nums; }
.tile .l { color: var(--muted); font-size: 12px; text-transform: uppercase; letter-spacing: 0.05em; }
.tile.fail { background: var(--fail-bg); border-color: #f1b7b2; } .tile.fail .n { color: var(--fail); }
.tile.error { background: var(--error-bg); border-color: #f0d2a0; } .tile.error .n { color: var(--error); }
.tile.pass { background: var(--pass-bg); border-color: #b9dcbb; } .tile.pass .n { color: var(--pass); }
.tile.zero { background: var(--soft); border-color: var(--line); } .tile.zero .n { color: var(--muted); }
.overview { display: flex; flex-wrap: wrap; gap: 16px 56px; align-items: flex-start; }
.run-info { flex: 1 1 520px; display: grid; grid-template-columns: max-content 1fr; gap: 4px 18px; margin: 0; }
.run-info dt { color: var(--muted); } .run-info dd { margin: 0; overflow-wrap: anywhere; }
.by-check { border-collapse: collapse; font-size: 13px; }
.by-check th, .by-check td { padding: 3px 12px 3px 0; text-align: right; font-variant-numeric: tabular-nums; }
.by-check th:first-child, .by-check td:first-child { text-align: left; }
.by-check thead th { color: var(--muted); font-weight: 600; border-bottom: 1px solid var(--line); }
table.results { width: 100%; border-collapse: collapse; font-size: 13px; }
table.results th { text-align: left; color: var(--muted); font-weight: 600; border-bottom: 2px solid var(--line); padding: 6px 8px; position: sticky; top: 0; background: #fff; }
table.results td { border-bottom: 1px solid #eceef1; padding: 5px 8px; vertical-align: top; }
table.results td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
table.results td.case { overflow-wrap: anywhere; }
table.results tr.fail td { background: var(--fail-bg); } table.results tr.error td { background: var(--error-bg); }
table.results tr.fail td:first-child { box-shadow: inset 4px 0 0 var(--fail); }
table.results tr.error td:first-child { box-shadow: inset 4px 0 0 var(--error); }
.badge { display: inline-block; min-width: 52px; text-align: center; border-radius: 4px; padding: 1px 6px; font-size: 11.5px; font-weight: 700; letter-spacing: 0.04em; color: #fff; }
.badge.pass { background: var(--pass); } .badge.fail { background: var(--fail); } .badge.error { background: var(--error); }
.badge.na { background: #8a939d; }
.pbad { color: var(--fail); font-weight: 600; }
.toolbar { margin: 0 0 10px; } .toolbar button { font: inherit; font-size: 12.5px; padding: 3px 10px; margin-right: 6px; border: 1px solid var(--line); border-radius: 4px; background: var(--soft); cursor: pointer; }
details.result { border: 1px solid var(--line); border-radius: 8px; margin: 0 0 12px; background: #fff; }
details.result.fail { border-color: #eba39c; border-left: 5px solid var(--fail); }
details.result.error { border-color: #e8c07e; border-left: 5px solid var(--error); }
details.result.pass { border-left: 5px solid var(--pass); }
details.result > summary { cursor: pointer; padding: 9px 14px; list-style-position: outside; margin-left: 14px; }
details.result > summary .case { font-weight: 600; overflow-wrap: anywhere; }
details.result > summary .check { color: var(--muted); margin: 0 6px; }
details.result > summary .sum { color: var(--muted); }
details.result.fail > summary { background: var(--fail-bg); border-radius: 0 6px 0 0; }
details.result.error > summary { background: var(--error-bg); border-radius: 0 6px 0 0; }
.body { padding: 4px 16px 14px; }
.message { margin: 10px 0; padding: 8px 12px; border-radius: 6px; white-space: pre-wrap; overflow-wrap: anywhere; }
.fail .message { background: var(--fail-bg); border: 1px solid #f1b7b2; }
.error .message { background: var(--error-bg); border: 1px solid #f0d2a0; }
.pass .message { background: var(--soft); border: 1px solid var(--line); }
.facts { display: flex; flex-wrap: wrap; gap: 4px 22px; margin: 8px 0; color: var(--muted); font-size: 13px; }
.facts b { color: var(--ink); font-weight: 600; font-variant-numeric: tabular-nums; }
.rerun { margin: 8px 0 12px; }
.rerun pre { margin: 4px 0 0; padding: 8px 12px; background: #1f2328; color: #f0f2f4; border-radius: 6px; white-space: pre-wrap; overflow-wrap: anywhere; user-select: all; }
h3 { font-size: 13px; text-transform: uppercase; letter-spacing: 0.05em; color: var(--muted); margin: 16px 0 6px; }
dl.figures { display: grid; grid-template-columns: repeat(auto-fill, minmax(250px, 1fr)); gap: 0 24px; margin: 0; font-size: 13px; }
dl.figures div { display: flex; justify-content: space-between; gap: 12px; border-bottom: 1px dotted var(--line); padding: 2px 0; }
dl.figures dt { color: var(--muted); overflow-wrap: anywhere; } dl.figures dd { margin: 0; font-variant-numeric: tabular-nums; white-space: nowrap; }
.plots { display: flex; flex-wrap: wrap; gap: 8px 28px; align-items: flex-start; }
figure { margin: 8px 0; max-width: 100%; }
figcaption { font-weight: 600; margin-bottom: 2px; }
svg.plot { display: block; max-width: 100%; height: auto; }
svg.plot text { font-family: inherit; }
svg.plot .axis-label, svg.plot .panel-title { font-weight: 600; }
svg.plot .legend-title { fill: #5f6773; }
svg.plot image.cells { image-rendering: pixelated; }
table.evidence { border-collapse: separate; border-spacing: 0; font-size: 12.5px; }
.table-title { font-weight: 600; margin: 10px 0 4px; }
.table-scroll { max-width: 100%; overflow-x: auto; margin: 0 0 10px; }
@media screen { .table-scroll { max-height: 460px; overflow-y: auto; } table.evidence thead th { position: sticky; top: 0; } }
table.evidence th, table.evidence td { border-right: 1px solid var(--line); border-bottom: 1px solid var(--line); padding: 3px 8px; text-align: left; }
table.evidence tr > :first-child { border-left: 1px solid var(--line); } table.evidence thead th { border-top: 1px solid var(--line); }
table.evidence th { background: var(--soft); font-weight: 600; }
table.evidence td { font-family: ui-monospace, "DejaVu Sans Mono", monospace; font-size: 12px; }
.note { color: var(--muted); font-size: 12.5px; }
.top { font-size: 12.5px; }
footer { color: var(--muted); font-size: 12px; padding-top: 20px; padding-bottom: 30px; }
@media print {
  body { font-size: 10pt; }
  main, .banner-inner, footer { max-width: none; padding: 0 6mm; }
  .banner, .badge, .tile, table.results td, details.result > summary, .message, .rerun pre, svg.plot { print-color-adjust: exact; -webkit-print-color-adjust: exact; }
  .toolbar, .top { display: none; }
  table.results th { position: static; }
  table.results tr, figure, dl.figures div, .tile { break-inside: avoid; }
  details.result { break-inside: auto; }
  details.result > summary { break-after: avoid; }
  .rerun pre { background: #fff; color: #000; border: 1px solid #999; }
  a { color: inherit; }
}
)CSS";

// Opens the details a link points at, and lets the buttons open or close them
// all. The page works without it: the failures are open already.
constexpr const char* kScript = R"JS(
(function () {
  function openTarget() {
    var target = location.hash ? document.getElementById(location.hash.slice(1)) : null;
    if (target) { if (target.tagName === 'DETAILS') { target.open = true; } target.scrollIntoView(); }
  }
  window.addEventListener('hashchange', openTarget);
  document.querySelectorAll('button[data-open]').forEach(function (button) {
    button.hidden = false;
    button.addEventListener('click', function () {
      var open = button.getAttribute('data-open') === 'all';
      document.querySelectorAll('details.result').forEach(function (d) { d.open = open; });
    });
  });
  if (location.hash) { openTarget(); }
})();
)JS";

std::string verdict_class(Verdict v) {
    switch (v) {
        case Verdict::Pass: return "pass";
        case Verdict::Fail: return "fail";
        case Verdict::Error: return "error";
        case Verdict::NotApplicable: return "na";
    }
    return "error";
}

std::string badge(Verdict v) {
    return fmt::format("<span class=\"badge {}\">{}</span>", verdict_class(v), escaped(to_string(v)));
}

std::string anchor(std::size_t index) { return fmt::format("r-{}", index); }

/// The order of the table and the details: failures, then errors, then passes,
/// then the checks that do not apply, each in registry order.
std::vector<std::size_t> display_order(const RunResult& run) {
    std::vector<std::size_t> order(run.results.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    const auto rank = [&](std::size_t i) {
        switch (run.results[i].verdict) {
            case Verdict::Fail: return 0;
            case Verdict::Error: return 1;
            case Verdict::Pass: return 2;
            case Verdict::NotApplicable: return 3;
        }
        return 1;
    };
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rank(a) < rank(b); });
    return order;
}

std::string plural(int n, std::string_view one, std::string_view many) {
    return fmt::format("{} {}", n, n == 1 ? one : many);
}

void append_banner(std::string& html, const RunResult& run) {
    const int failed = run.count(Verdict::Fail), errors = run.count(Verdict::Error);
    const int total = static_cast<int>(run.results.size());
    std::string cls = failed > 0 ? "fail" : errors > 0 ? "error" : total == 0 ? "empty" : "pass";
    std::string headline, line;
    if (total == 0) {
        headline = "NO CHECKS RAN";
        line = "The selection matched no (case, check) pair.";
    } else if (failed == 0 && errors == 0) {
        headline = "PASSED";
        const int not_applicable = run.count(Verdict::NotApplicable);
        line = not_applicable == 0
                   ? fmt::format("All {} passed.", plural(total, "check", "checks"))
                   : fmt::format("Every check that applies passed ({} of {}); {} not applicable.",
                                 total - not_applicable, total, not_applicable);
    } else {
        headline = failed > 0 ? "FAILED" : "ERRORS";
        std::vector<std::string> parts;
        if (failed > 0) parts.push_back(fmt::format("{} failed", failed));
        if (errors > 0) parts.push_back(fmt::format("{} could not run", plural(errors, "check", "checks")));
        line = fmt::format("{} of {}: {}.", failed + errors, plural(total, "check", "checks"),
                           parts.size() == 2 ? parts[0] + ", " + parts[1] : parts[0]);
    }
    html += fmt::format(
        "<header class=\"banner {}\"><div class=\"banner-inner\"><h1><span class=\"tool\">warpcheck</span>{}</h1>"
        "<p>{}</p></div></header>\n",
        cls, escaped(headline), escaped(line));
}

void append_summary(std::string& html, const RunResult& run) {
    const RunInfo& info = run.info;
    const int passed = run.count(Verdict::Pass), failed = run.count(Verdict::Fail), errors = run.count(Verdict::Error);
    const auto tile = [&](std::string_view cls, std::string value, std::string_view label) {
        html += fmt::format("<div class=\"tile {}\"><span class=\"n\">{}</span><span class=\"l\">{}</span></div>", cls,
                            escaped(value), escaped(label));
    };
    html += "<section id=\"summary\"><div class=\"tiles\">";
    tile(failed > 0 ? "fail" : "fail zero", std::to_string(failed), "failed");
    tile(errors > 0 ? "error" : "error zero", std::to_string(errors), "errors");
    tile("pass", std::to_string(passed), "passed");
    if (const int na = run.count(Verdict::NotApplicable); na > 0) tile("na", std::to_string(na), "not applicable");
    tile("", std::to_string(run.results.size()), "checks");
    tile("", format_seconds(info.wall_seconds), "wall time");
    html += "</div>\n<div class=\"overview\"><dl class=\"run-info\">";
    const auto row = [&](std::string_view term, const std::string& markup) {
        html += fmt::format("<dt>{}</dt><dd>{}</dd>", escaped(term), markup);
    };
    if (!info.started_at.empty()) row("Started", escaped(info.started_at));
    row("Seed", fmt::format("<span class=\"mono\">{}</span>", info.seed));
    row("Samples", fmt::format("{} per statistical check", escaped(format_grouped(static_cast<double>(info.samples)))));
    row("Significance",
        fmt::format("family-wise &#945; = {} &#8594; <b>{}</b> per test (&#352;id&#225;k correction over {})",
                    escaped(format_probability(info.family_alpha)), escaped(format_probability(info.per_test_alpha)),
                    escaped(plural(info.statistical_tests, "statistical test", "statistical tests"))));
    row("Threads", std::to_string(info.threads));
    if (!info.machine.empty()) row("Machine", escaped(info.machine));
    if (!info.compiler.empty()) row("Compiler", escaped(info.compiler));
    if (!info.tool_version.empty()) row("Version", escaped("warpcheck " + info.tool_version));
    if (!info.command_line.empty()) row("Command", "<code>" + escaped(info.command_line) + "</code>");
    html += "</dl>\n";

    // Counts per check, in the order checks first appear.
    std::vector<std::string> checks;
    std::map<std::string, std::array<int, 4>> counts;  // by Verdict
    for (const auto& r : run.results) {
        if (!counts.count(r.check_name)) checks.push_back(r.check_name);
        counts[r.check_name][static_cast<std::size_t>(r.verdict)]++;
    }
    if (checks.size() > 1) {
        html += "<table class=\"by-check\"><thead><tr><th>check</th><th>passed</th><th>failed</th><th>errors</th></tr></thead><tbody>";
        for (const auto& c : checks) {
            const auto& n = counts[c];
            const auto cell = [](int v, std::string_view cls) {
                return v > 0 && !cls.empty() ? fmt::format("<td class=\"pbad\">{}</td>", v) : fmt::format("<td>{}</td>", v);
            };
            html += fmt::format("<tr><td>{}</td>{}{}{}</tr>", escaped(c), cell(n[0], ""), cell(n[1], "bad"), cell(n[2], "bad"));
        }
        html += "</tbody></table>";
    }
    html += "</div></section>\n";
}

std::string p_value_cell(const CheckResult& r) {
    if (!r.p_value) return "";
    const bool below = r.level && !(*r.p_value >= *r.level);
    return fmt::format("<span{}>{}</span>", below ? " class=\"pbad\"" : "", escaped(format_probability(*r.p_value)));
}

void append_table(std::string& html, const RunResult& run, const std::vector<std::size_t>& order) {
    html += "<section id=\"results\"><h2>Results</h2>\n";
    if (order.empty()) {
        html += "<p class=\"note\">No results.</p></section>\n";
        return;
    }
    html += "<table class=\"results\"><thead><tr><th>verdict</th><th>case</th><th>check</th><th>summary</th>"
            "<th>p-value</th><th>time</th></tr></thead>\n<tbody>\n";
    for (std::size_t i : order) {
        const CheckResult& r = run.results[i];
        html += fmt::format(
            "<tr class=\"{}\"><td>{}</td><td class=\"case mono\"><a href=\"#{}\">{}</a></td><td>{}</td><td>{}</td>"
            "<td class=\"num\">{}</td><td class=\"num\">{}</td></tr>\n",
            verdict_class(r.verdict), badge(r.verdict), anchor(i), escaped(r.case_name), escaped(r.check_name),
            escaped(r.summary), p_value_cell(r), escaped(format_seconds(r.seconds)));
    }
    html += "</tbody></table></section>\n";
}

void append_evidence_table(std::string& html, const Table& table) {
    constexpr std::size_t kMaxRows = 500;
    if (!table.title.empty()) html += "<p class=\"table-title\">" + escaped(table.title) + "</p>";
    html += "<div class=\"table-scroll\"><table class=\"evidence\">";
    if (!table.columns.empty()) {
        html += "<thead><tr>";
        for (const auto& c : table.columns) html += "<th>" + escaped(c) + "</th>";
        html += "</tr></thead>";
    }
    html += "<tbody>";
    for (std::size_t i = 0; i < table.rows.size() && i < kMaxRows; ++i) {
        html += "<tr>";
        for (const auto& cell : table.rows[i]) html += "<td>" + escaped(cell) + "</td>";
        html += "</tr>";
    }
    html += "</tbody></table></div>\n";
    if (table.rows.size() > kMaxRows)
        html += fmt::format("<p class=\"note\">{} more rows are in the JSON report.</p>\n", table.rows.size() - kMaxRows);
}

void append_details(std::string& html, const RunResult& run, std::size_t index) {
    const CheckResult& r = run.results[index];
    const std::string cls = verdict_class(r.verdict);
    html += fmt::format("<details class=\"result {}\" id=\"{}\"{}>\n<summary>{} <span class=\"case mono\">{}</span>"
                        "<span class=\"check\">&#183; {}</span>{}</summary>\n<div class=\"body\">\n",
                        cls, anchor(index),
                        r.verdict == Verdict::Pass || r.verdict == Verdict::NotApplicable ? "" : " open=\"open\"",
                        badge(r.verdict),
                        escaped(r.case_name), escaped(r.check_name),
                        r.summary.empty() ? "" : " <span class=\"sum\">&#8212; " + escaped(r.summary) + "</span>");
    if (!r.message.empty()) html += "<p class=\"message\">" + escaped(r.message) + "</p>\n";

    html += "<div class=\"facts\">";
    const auto fact = [&](std::string_view name, const std::string& value) {
        html += fmt::format("<span>{} <b>{}</b></span>", escaped(name), escaped(value));
    };
    if (r.p_value) fact("p-value", format_probability(*r.p_value));
    if (r.level) fact("level", format_probability(*r.level));
    if (r.samples > 0) fact("samples", format_grouped(static_cast<double>(r.samples)));
    fact("time", format_seconds(r.seconds));
    // Where that time went (--timings prints the same): integration, sampling, ...
    for (const PhaseTime& p : r.phases) fact(p.phase, format_seconds(p.seconds));
    fact("stream seed", fmt::format("{:#x}", r.stream_seed));
    fact("sequence", fmt::format("{:#x}", r.stream_sequence));
    html += "</div>\n";
    if (!r.rerun_command.empty())
        html += "<div class=\"rerun\"><span class=\"note\">Rerun just this check:</span><pre><code>" +
                escaped(r.rerun_command) + "</code></pre></div>\n";

    if (!r.figures.empty()) {
        html += "<h3>Figures</h3><dl class=\"figures\">";
        for (const Figure& f : r.figures)
            html += fmt::format("<div><dt>{}</dt><dd title=\"{}\">{}</dd></div>", escaped(f.name),
                                escaped(std::isfinite(f.value) ? fmt::format("{}", f.value) : format_number(f.value)),
                                escaped(format_grouped(f.value)));
        html += "</dl>\n";
    }
    if (!r.plots.empty()) {
        html += "<h3>Plots</h3><div class=\"plots\">\n";
        for (std::size_t p = 0; p < r.plots.size(); ++p) {
            const Plot& plot = r.plots[p];
            SvgOptions options;
            options.id_prefix = fmt::format("p{}-{}", index, p);
            html += "<figure>";
            if (!plot.title.empty()) html += "<figcaption>" + escaped(plot.title) + "</figcaption>";
            html += render_svg(plot, options);
            html += "</figure>\n";
        }
        html += "</div>\n";
    }
    if (!r.tables.empty()) {
        html += "<h3>Tables</h3>\n";
        for (const Table& t : r.tables) append_evidence_table(html, t);
    }
    html += "<a class=\"top\" href=\"#results\">&#8593; back to the results</a>\n</div></details>\n";
}

}  // namespace

std::string render_html(const RunResult& run) {
    const int failed = run.count(Verdict::Fail), errors = run.count(Verdict::Error);
    const std::vector<std::size_t> order = display_order(run);
    std::string html;
    html.reserve(1 << 20);
    html += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"/>\n"
            "<meta name=\"generator\" content=\"warpcheck\"/>\n";
    html += fmt::format("<title>warpcheck: {}</title>\n",
                        escaped(failed + errors > 0 ? fmt::format("{} failed, {} errors of {}", failed, errors, run.results.size())
                                                    : fmt::format("all {} passed", run.results.size())));
    html += "<style>";
    html += kStyle;
    html += "</style>\n</head>\n<body>\n";
    append_banner(html, run);
    html += "<main>\n";
    append_summary(html, run);
    append_table(html, run, order);
    if (!order.empty()) {
        html += "<section id=\"details\"><h2>Details</h2>\n"
                "<div class=\"toolbar\"><button type=\"button\" data-open=\"all\" hidden=\"hidden\">Expand all</button>"
                "<button type=\"button\" data-open=\"none\" hidden=\"hidden\">Collapse all</button></div>\n";
        for (std::size_t i : order) append_details(html, run, i);
        html += "</section>\n";
    }
    html += "</main>\n<footer>";
    html += escaped(fmt::format("Generated by warpcheck{}{}.", run.info.tool_version.empty() ? "" : " " + run.info.tool_version,
                                run.info.started_at.empty() ? "" : " for the run started " + run.info.started_at));
    html += " Self-contained: no scripts, styles or fonts are loaded from anywhere.</footer>\n<script>";
    html += kScript;
    html += "</script>\n</body>\n</html>\n";
    return html;
}

void write_html_report(const RunResult& run, const std::string& path) {
    write_file_atomically(path, render_html(run));
}

}  // namespace warpcheck
