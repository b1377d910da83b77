// The HTML report: one self-contained page (inline CSS, script, SVG and PNG; no
// network) that shows a run at a glance and the evidence of every check.
//
// The results are one list, grouped by family, each row a <details> whose
// summary is the table row and whose body is the evidence; a family whose
// rows carry points across its cases (a BSDF's albedo against theta_o) shows
// those plots above its rows. Failures and errors
// (the first kMaxOpenRows of them) are open, their evidence inline, so the page
// shows them whole without script and in print. Every other row's evidence is
// packed with its check's (pack_details) and inflated by the script when the
// row opens. That keeps a report of hundreds of rows with plots well under a
// megabyte and quick to open: the browser parses a few blobs, not the plots.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "reports/atomic_file.h"
#include "reports/family_plots.h"
#include "reports/html_report_parts.h"
#include "reports/outputs.h"
#include "reports/png.h"
#include "reports/render.h"
#include "reports/terminal_table.h"
#include "reports/text.h"

namespace warpcheck {
namespace {

/// Failures and errors shown open with their evidence inline; further ones are
/// packed and closed like passes, so a run where everything fails still opens quickly.
constexpr std::size_t kMaxOpenRows = 20;

std::string verdict_class(Verdict v) {
    switch (v) {
        case Verdict::Pass: return "pass";
        case Verdict::Fail: return "fail";
        case Verdict::Error: return "error";
        case Verdict::NotApplicable: return "na";
    }
    return "error";
}

/// A pass that could not have seen its stated effect reads "weak" (CheckResult::weak).
std::string badge(const CheckResult& r) {
    const bool weak = r.verdict == Verdict::Pass && !r.weak.empty();
    return fmt::format("<span class=\"badge {}\"{}>{}</span>", weak ? "weak" : verdict_class(r.verdict),
                       weak ? " title=\"" + escaped(r.weak) + "\"" : std::string(), escaped(verdict_word(r)));
}

std::string plural(std::size_t n, std::string_view one, std::string_view many) {
    return fmt::format("{} {}", n, n == 1 ? one : many);
}

void append_banner(std::string& html, const RunResult& run) {
    const int failed = run.count(Verdict::Fail), errors = run.count(Verdict::Error);
    const std::size_t total = run.results.size();
    const std::string cls = failed > 0 ? "fail" : errors > 0 ? "error" : total == 0 ? "empty" : "pass";
    std::string headline, line;
    if (total == 0) {
        headline = "NO CHECKS RAN";
        line = "The selection matched no (case, check) pair.";
    } else if (failed == 0 && errors == 0) {
        headline = "PASSED";
        const std::size_t na = static_cast<std::size_t>(run.count(Verdict::NotApplicable));
        line = na == 0 ? fmt::format("All {} passed.", plural(total, "check", "checks"))
                       : fmt::format("Every check that applies passed ({} of {}); {} not applicable.", total - na, total, na);
    } else {
        headline = failed > 0 ? "FAILED" : "ERRORS";
        std::vector<std::string> parts;
        if (failed > 0) parts.push_back(fmt::format("{} failed", failed));
        if (errors > 0) parts.push_back(fmt::format("{} could not run", plural(static_cast<std::size_t>(errors), "check", "checks")));
        line = fmt::format("{} of {}: {}.", failed + errors, plural(total, "check", "checks"),
                           parts.size() == 2 ? parts[0] + ", " + parts[1] : parts[0]);
        if (static_cast<std::size_t>(failed + errors) > kMaxOpenRows)
            line += fmt::format(" The first {} are open below; the others open with a click.", kMaxOpenRows);
    }
    html += fmt::format("<header class=\"banner {}\"><div class=\"banner-inner\"><h1><span class=\"tool\">warpcheck</span>{}</h1>"
                        "<p>{}</p></div></header>\n",
                        cls, escaped(headline), escaped(line));
}

void append_tiles(std::string& html, const RunResult& run) {
    const auto tile = [&](std::string_view cls, const std::string& value, std::string_view label) {
        html += fmt::format("<div class=\"tile {}\"><span class=\"n\">{}</span><span class=\"l\">{}</span></div>", cls,
                            escaped(value), escaped(label));
    };
    const int failed = run.count(Verdict::Fail), errors = run.count(Verdict::Error);
    html += "<div class=\"tiles\">";
    tile(failed > 0 ? "fail" : "fail zero", std::to_string(failed), "failed");
    tile(errors > 0 ? "error" : "error zero", std::to_string(errors), "errors");
    tile("pass", std::to_string(run.count(Verdict::Pass)), "passed");
    if (const int na = run.count(Verdict::NotApplicable); na > 0) tile("na", std::to_string(na), "not applicable");
    tile("", std::to_string(run.results.size()), "checks");
    tile("", format_seconds(run.info.wall_seconds), "wall time");
    html += "</div>\n";
}

void append_run_info(std::string& html, const RunInfo& info) {
    html += "<dl class=\"run-info\">";
    const auto row = [&](std::string_view term, const std::string& markup, bool wide = false) {
        html += fmt::format("<dt{0}>{1}</dt><dd{0}>{2}</dd>", wide ? " class=\"wide\"" : "", escaped(term), markup);
    };
    row("Significance",
        fmt::format("family-wise &#945; = {} &#8594; <b>{}</b> per test (&#352;id&#225;k correction over {})",
                    escaped(format_probability(info.family_alpha)), escaped(format_probability(info.per_test_alpha)),
                    escaped(plural(static_cast<std::size_t>(std::max(info.statistical_tests, 0)), "statistical test",
                                   "statistical tests"))),
        true);
    row("Seed", fmt::format("<span class=\"mono\">{}</span>", info.seed));
    row("Samples", escaped(format_grouped(static_cast<double>(info.samples))) + " per statistical check");
    row("Threads", std::to_string(info.threads));
    if (!info.started_at.empty()) row("Started", escaped(info.started_at));
    if (!info.machine.empty()) row("Machine", escaped(info.machine));
    if (!info.compiler.empty()) row("Compiler", escaped(info.compiler));
    if (!info.tool_version.empty()) row("Version", escaped("warpcheck " + info.tool_version));
    if (info.shard_count > 0) row("Shard", fmt::format("{} of {} ({} jobs in all)", info.shard_index, info.shard_count, info.run_jobs));
    if (!info.command_line.empty()) row("Command", "<code>" + escaped(info.command_line) + "</code>", true);
    html += "</dl>\n";
}

/// Counts per check, in the order checks first appear, beside what each judges
/// and what its p-value is: the legend of the results below.
void append_checks(std::string& html, const RunResult& run) {
    std::vector<std::string> checks;
    std::map<std::string, std::array<int, 4>> counts;  // by Verdict
    for (const auto& r : run.results) {
        if (!counts.count(r.check_name)) checks.push_back(r.check_name);
        counts[r.check_name][static_cast<std::size_t>(r.verdict)]++;
    }
    if (checks.empty()) return;
    html += "<h2 id=\"checks\">Checks and how they are judged</h2>\n<table class=\"checks\"><thead><tr><th>check</th><th>pass</th>"
            "<th>fail</th><th>error</th><th>n/a</th><th>what is judged</th><th>its p-value (compared with the per-test level)</th>"
            "</tr></thead><tbody>\n";
    for (const auto& c : checks) {
        const auto& n = counts[c];
        const auto cell = [](int v, bool bad) { return fmt::format("<td class=\"n{}\">{}</td>", v > 0 && bad ? " bad" : "", v); };
        CheckLegend legend;  // from the run (RunInfo::legends): the check's own words
        for (const CheckLegend& l : run.info.legends)
            if (l.check == c) legend = l;
        html += fmt::format("<tr><td class=\"mono\">{}</td>{}{}{}{}<td class=\"what\">{}</td><td class=\"what\">{}</td></tr>\n",
                            escaped(c), cell(n[0], false), cell(n[1], true), cell(n[2], true), cell(n[3], false),
                            escaped(legend.judged), escaped(legend.p_value.empty() ? "\u2014" : legend.p_value));
    }
    html += "</tbody></table>\n<p class=\"note\">The <b>margin</b> column mirrors the terminal's: a p-value over the per-test "
            "level (a row fails below 1\u00d7), or the largest error over its tolerance (fails above 1). Its bar fills on a log "
            "scale from a thousandth of the limit to the limit. Each row's <b>Judged</b> table lists every quantity against "
            "its limit.</p>\n";
}

/// The passing rows closest to their limits, as the terminal lists them: the
/// three smallest p-values over the level and the three largest fractions of a
/// tolerance, each linking to its row.
void append_weakest(std::string& html, const RunResult& run) {
    struct Entry {
        double key;
        std::size_t row;
        std::string margin, figure;
    };
    std::vector<Entry> by_p, by_tolerance;
    for (std::size_t i = 0; i < run.results.size(); ++i) {
        const CheckResult& r = run.results[i];
        if (r.verdict != Verdict::Pass) continue;
        const RowMargin m = row_margin(r);
        if (m.p_over_level) by_p.push_back({*m.p_over_level, i, margin_text({m.p_over_level, std::nullopt, {}}), "p-value"});
        if (m.of_tolerance) by_tolerance.push_back({-*m.of_tolerance, i, margin_text({std::nullopt, m.of_tolerance, {}}), m.tolerance_figure});
    }
    if (by_p.empty() && by_tolerance.empty()) return;
    html += "<h2>Closest to their limits</h2><ul class=\"weakest\">";
    for (auto* list : {&by_p, &by_tolerance}) {
        std::stable_sort(list->begin(), list->end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
        for (std::size_t k = 0; k < list->size() && k < 3; ++k) {
            const Entry& e = (*list)[k];
            const CheckResult& r = run.results[e.row];
            html += fmt::format("<li><span class=\"wm\">{}</span> <a href=\"#r-{}\"><span class=\"mono\">{}</span> \u00b7 {}</a> "
                                "<span class=\"note\">({})</span></li>",
                                escaped(e.margin), e.row, escaped(r.case_name), escaped(r.check_name), escaped(e.figure));
        }
    }
    html += "</ul>\n";
}

/// The margin cell: the terminal's text (a row that did not pass shows it only
/// when that is what failed it) with a gauge of how close the row came.
std::string html_margin_cell(const CheckResult& r) {
    const RowMargin m = row_margin(r);
    const bool past = (m.p_over_level && !(*m.p_over_level >= 1.0)) || (m.of_tolerance && *m.of_tolerance > 1.0);
    // The terminal's text, or the tolerance's when a row with both came closer to that.
    const bool tolerance_closer = m.p_over_level && m.of_tolerance && *m.of_tolerance * *m.p_over_level > 1.0;
    const std::string text = margin_text(tolerance_closer ? RowMargin{std::nullopt, m.of_tolerance, m.tolerance_figure} : m);
    if (text.empty() || (r.verdict != Verdict::Pass && !past)) return "<span class=\"m\"></span>";
    const double c = html::closeness(r).value_or(0.0);
    const double fill = std::clamp((std::log10(std::max(c, 1e-300)) + 3.0) / 3.0, 0.0, 1.0);
    const std::string title = m.p_over_level && !tolerance_closer ? fmt::format("p-value {} is {} times the level", format_probability(r.p_value.value_or(NAN)), fmt::format("{:.3g}", *m.p_over_level))
                                             : fmt::format("{} is {:.3g} of its limit", m.tolerance_figure, m.of_tolerance.value_or(NAN));
    return fmt::format("<span class=\"m\" title=\"{}\"><span class=\"gauge{}\"><i style=\"width:{:.0f}%\"></i></span>{}</span>",
                       escaped(title), c >= 1.0 ? " over" : c >= 0.3 ? " near" : "", fill * 100.0, escaped(text));
}

std::string p_value_cell(const CheckResult& r) {
    if (!r.p_value) return "<span class=\"p\"></span>";
    const bool below = r.level && !(*r.p_value >= *r.level);
    return fmt::format("<span class=\"p{}\"{}>{}</span>", below ? " bad" : "",
                       r.level ? fmt::format(" title=\"compared with the level {}\"", escaped(format_probability(*r.level))) : "",
                       escaped(format_probability(*r.p_value)));
}

/// The case name, its family part quieter (the group's heading says it) and
/// the whole name as the tooltip.
std::string case_cell(const std::string& name) {
    const std::size_t bracket = name.find('[');
    if (bracket == std::string::npos) return "<span class=\"case mono\">" + escaped(name) + "</span>";
    return "<span class=\"case mono\" title=\"" + escaped(name) + "\"><span class=\"fam-part\">" +
           escaped(name.substr(0, bracket)) + "</span>" + escaped(name.substr(bracket)) + "</span>";
}

/// The details of the rows that are not open, packed: grouped by check in
/// the order of the page (similar rows side by side compress several times
/// better than one by one), a group closed at ~1 MB of markup so that opening
/// a row never inflates much more than that. Each group is a zlib stream of a
/// JSON object {row index: markup}, in base64.
struct Packs {
    std::map<std::size_t, std::size_t> pack_of;  ///< row index -> pack id
    std::vector<std::string> base64;             ///< by pack id
};

Packs pack_details(const RunResult& run, const std::vector<html::FamilyGroup>& groups, const std::set<std::size_t>& open) {
    constexpr std::size_t kPackBytes = 1 << 20;
    std::map<std::string, std::vector<std::size_t>> by_check;
    std::vector<std::string> check_order;
    for (const auto& g : groups)
        for (std::size_t i : g.rows) {
            if (open.count(i)) continue;
            auto [it, added] = by_check.try_emplace(run.results[i].check_name);
            if (added) check_order.push_back(it->first);
            it->second.push_back(i);
        }
    Packs packs;
    for (const auto& check : check_order) {
        nlohmann::json bodies = nlohmann::json::object();
        std::size_t bytes = 0;
        const auto close = [&] {
            if (bodies.empty()) return;
            packs.base64.push_back(base64(zlib_compress(bodies.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace))));
            bodies = nlohmann::json::object(), bytes = 0;
        };
        for (std::size_t i : by_check[check]) {
            std::string body = html::row_body(run, i);
            bytes += body.size();
            packs.pack_of[i] = packs.base64.size();
            bodies[std::to_string(i)] = std::move(body);
            if (bytes >= kPackBytes) close();
        }
        close();
    }
    return packs;
}

/// The row: its summary line, and its details inline (open) or in a pack.
void append_row(std::string& html, const RunResult& run, std::size_t i, const Packs& packs) {
    const CheckResult& r = run.results[i];
    const auto pack = packs.pack_of.find(i);
    const bool open = pack == packs.pack_of.end();
    html += fmt::format("<details class=\"r {0}\" id=\"r-{1}\" data-v=\"{0}\" data-c=\"{2}\"{3}{4}>\n<summary>"
                        "<span class=\"v\">{5}</span>{6}<span class=\"chk\">{2}</span>{7}<span class=\"key\">{8}</span>{9}"
                        "<span class=\"t\">{10}</span></summary>\n",
                        verdict_class(r.verdict), i, escaped(r.check_name),
                        r.message.empty() ? "" : " data-s=\"" + escaped(r.message) + "\"",
                        open ? " open=\"open\"" : fmt::format(" data-p=\"{}\"", pack->second), badge(r),
                        case_cell(r.case_name), html_margin_cell(r), escaped(r.summary), p_value_cell(r),
                        escaped(format_seconds(r.seconds)));
    if (open) html += "<div class=\"body\">\n" + html::row_body(run, i) + "</div>";
    else html += "<div class=\"body\"></div>";
    html += "</details>\n";
}

void append_toolbar(std::string& html, const RunResult& run, const std::vector<html::FamilyGroup>& groups) {
    html += "<div class=\"toolbar needs-js\" hidden=\"hidden\" role=\"search\">"
            "<input type=\"search\" id=\"q\" placeholder=\"Search case, check, summary, message  ( / )\" aria-label=\"Search\"/>";
    const std::array<std::pair<const char*, Verdict>, 4> verdicts{
        {{"failed", Verdict::Fail}, {"errors", Verdict::Error}, {"passed", Verdict::Pass}, {"n/a", Verdict::NotApplicable}}};
    html += fmt::format("<button type=\"button\" data-verdict=\"\" aria-pressed=\"true\">all {}</button>", run.results.size());
    for (const auto& [label, v] : verdicts)
        if (const int n = run.count(v); n > 0 || v != Verdict::NotApplicable)
            html += fmt::format("<button type=\"button\" data-verdict=\"{}\" aria-pressed=\"false\">{} {}</button>", verdict_class(v), label, n);
    std::set<std::string> checks;
    for (const auto& r : run.results) checks.insert(r.check_name);
    html += "<select id=\"f-check\" aria-label=\"Check\"><option value=\"\">every check</option>";
    for (const auto& c : checks) html += fmt::format("<option value=\"{0}\">{0}</option>", escaped(c));
    html += "</select><select id=\"f-family\" aria-label=\"Family\"><option value=\"\">every family</option>";
    std::vector<std::string> families;
    for (const auto& g : groups) families.push_back(g.family);
    std::sort(families.begin(), families.end());
    for (const auto& f : families) html += fmt::format("<option value=\"{0}\">{0}</option>", escaped(f));
    html += "</select><button type=\"button\" data-open=\"all\">Expand all</button><button type=\"button\" data-open=\"none\">"
            "Collapse all</button><span class=\"shown\" id=\"shown\"></span></div>\n";
}

std::string family_counts(const RunResult& run, const html::FamilyGroup& g) {
    std::set<std::string> cases;
    std::array<int, 4> n{};
    for (std::size_t i : g.rows) cases.insert(run.results[i].case_name), n[static_cast<std::size_t>(run.results[i].verdict)]++;
    std::string text = fmt::format("{} \u00b7 {}", plural(cases.size(), "case", "cases"), plural(g.rows.size(), "check", "checks"));
    if (n[1] > 0) text += fmt::format(" \u00b7 <span class=\"bad\">{} failed</span>", n[1]);
    if (n[2] > 0) text += fmt::format(" \u00b7 <span class=\"bad\">{} errors</span>", n[2]);
    if (n[1] + n[2] == 0) text += n[3] > 0 ? fmt::format(" \u00b7 all passed that apply ({} n/a)", n[3]) : " \u00b7 all passed";
    return text;
}

/// The plots across the cases of a family (reports/family_plots.h), before
/// its rows: the rows' points gathered, their limits drawn as the report
/// draws every limit.
void append_family_plots(std::string& html, const std::vector<FamilyPlot>& plots, const std::string& family) {
    std::string figures, titles;
    for (std::size_t i = 0; i < plots.size(); ++i) {
        if (plots[i].family != family) continue;
        SvgOptions options;
        options.id_prefix = fmt::format("f{}", i);
        options.width = 520.0;
        for (const Figure& l : plots[i].limits)
            options.limits.push_back({false, l.value, l.name + " " + format_number(l.value)});
        figures += "<figure><figcaption>" + escaped(plots[i].plot.title) + "</figcaption>" +
                   render_svg(plots[i].plot, options);
        if (plots[i].plot.log_y) figures += "<p class=\"note\">A value of 0 has no place on the log axis: not drawn.</p>";
        figures += "</figure>\n";
        titles += (titles.empty() ? "" : "; ") + plots[i].plot.title;
    }
    if (figures.empty()) return;
    html += "<details class=\"across\" open=\"open\"><summary>Across the family: " + escaped(titles) +
            "</summary><div class=\"plots\">\n" + figures + "</div></details>\n";
}

void append_results(std::string& html, const RunResult& run) {
    html += "<section id=\"results\"><h2>Results</h2>\n";
    if (run.results.empty()) {
        html += "<p class=\"note\">No results.</p></section>\n";
        return;
    }
    const std::vector<html::FamilyGroup> groups = html::family_groups(run);
    append_toolbar(html, run, groups);
    html += "<div class=\"cols\" aria-hidden=\"true\"><span>verdict</span><span>case</span><span>check</span><span>margin</span>"
            "<span>key figure</span><span>p-value</span><span>time</span></div>\n";
    std::set<std::size_t> open;
    for (const auto& g : groups)
        for (std::size_t i : g.rows)
            if (const Verdict v = run.results[i].verdict; (v == Verdict::Fail || v == Verdict::Error) && open.size() < kMaxOpenRows)
                open.insert(i);
    const Packs packs = pack_details(run, groups, open);
    const std::vector<FamilyPlot> across = family_plots(run.results);
    for (const auto& g : groups) {
        html += fmt::format("<section class=\"fam\" data-f=\"{0}\"><h3><span class=\"fn\">{0}</span><span class=\"fc\">{1}</span></h3>\n",
                            escaped(g.family), family_counts(run, g));
        append_family_plots(html, across, g.family);
        for (std::size_t i : g.rows) append_row(html, run, i, packs);
        html += "</section>\n";
    }
    html += "<p class=\"empty-result\" id=\"no-match\" hidden=\"hidden\">No row matches the search and filters.</p></section>\n";
    if (!packs.base64.empty())
        html += "<noscript><p class=\"note\">The details of rows that are not open need JavaScript to unpack; the JSON report "
                "(--json) has every figure.</p></noscript>\n";
    for (std::size_t p = 0; p < packs.base64.size(); ++p)
        html += fmt::format("<script type=\"application/x-warpcheck-pack\" id=\"pack-{}\">{}</script>\n", p, packs.base64[p]);
}

}  // namespace

std::string render_html(const RunResult& run) {
    const int failed = run.count(Verdict::Fail), errors = run.count(Verdict::Error);
    std::string html;
    html.reserve(1 << 20);
    html += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"/>\n<meta name=\"generator\" content=\"warpcheck\"/>\n";
    html += fmt::format("<title>warpcheck: {}</title>\n",
                        escaped(failed + errors > 0 ? fmt::format("{} failed, {} errors of {}", failed, errors, run.results.size())
                                                    : fmt::format("all {} passed", run.results.size())));
    html += "<style>" + std::string(html::style_sheet()) + "</style>\n</head>\n<body>\n";
    append_banner(html, run);
    html += "<main>\n<section id=\"summary\">";
    append_tiles(html, run);
    append_run_info(html, run.info);
    append_checks(html, run);
    append_weakest(html, run);
    html += "</section>\n";
    append_results(html, run);
    html += "</main>\n<footer>";
    html += escaped(fmt::format("Generated by warpcheck{}{}.", run.info.tool_version.empty() ? "" : " " + run.info.tool_version,
                                run.info.started_at.empty() ? "" : " for the run started " + run.info.started_at));
    html += " Self-contained: nothing is loaded from anywhere. Rows that are not open keep their details packed until "
            "opened.</footer>\n<script>//<![CDATA[";  // the page is also well-formed XML
    html += html::script();
    html += "//]]></script>\n</body>\n</html>\n";
    return html;
}

void write_html_report(const RunResult& run, const std::string& path) {
    write_file_atomically(path, render_html(run));
}

}  // namespace warpcheck
