// One row of the HTML report: where it stands (its family group and its rank
// within it) and its details.
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "reports/html_report_parts.h"
#include "reports/svg_plot.h"
#include "reports/text.h"

namespace warpcheck::html {
namespace {

int verdict_rank(Verdict v) {
    switch (v) {
        case Verdict::Fail: return 0;
        case Verdict::Error: return 1;
        case Verdict::Pass: return 2;
        case Verdict::NotApplicable: return 3;
    }
    return 1;
}

std::string family_of(const std::string& case_name) { return case_name.substr(0, case_name.find('[')); }

/// Sorts first by verdict, then by closeness to the limit (closest first; a
/// row without a margin after those with one), then in registry order.
struct RowKey {
    int verdict = 0;
    double closeness = -1.0;
    std::size_t index = 0;
    bool operator<(const RowKey& o) const {
        if (verdict != o.verdict) return verdict < o.verdict;
        if (closeness != o.closeness) return closeness > o.closeness;
        return index < o.index;
    }
};

RowKey key_of(const RunResult& run, std::size_t i) {
    const CheckResult& r = run.results[i];
    return {verdict_rank(r.verdict), closeness(r).value_or(-1.0), i};
}

void append_evidence_table(std::string& html, const Table& table) {
    constexpr std::size_t kMaxRows = 200;
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

void append_facts(std::string& html, const CheckResult& r) {
    html += "<div class=\"facts\">";
    const auto fact = [&](std::string_view name, const std::string& value) {
        html += fmt::format("<span>{} <b>{}</b></span>", escaped(name), escaped(value));
    };
    if (r.p_value) fact("p-value", format_probability(*r.p_value));
    if (r.level) fact("level", format_probability(*r.level));
    if (r.samples > 0) fact("samples", format_grouped(static_cast<double>(r.samples)));
    fact("time", format_seconds(r.seconds));
    for (const PhaseTime& p : r.phases) fact(p.phase, format_seconds(p.seconds));  // as --timings prints them
    fact("stream seed", fmt::format("{:#x}", r.stream_seed));
    fact("sequence", fmt::format("{:#x}", r.stream_sequence));
    html += "</div>\n";
}

void append_judged(std::string& html, const CheckResult& r) {
    const std::vector<JudgedQuantity>& lines = r.judged;  // the check's own judgement
    if (lines.empty()) return;
    html += "<h4>Judged</h4><table class=\"judged\"><thead><tr><th>quantity</th><th>value</th><th>limit</th><th></th></tr>"
            "</thead><tbody>";
    using State = JudgedQuantity::State;
    for (const JudgedQuantity& l : lines) {
        const char* cls = l.state == State::Beyond ? " class=\"beyond\"" : l.state == State::Reported ? " class=\"reported\"" : "";
        const char* mark = l.state == State::Beyond ? "\u2717" : l.state == State::Within ? "\u2713" : "";
        html += fmt::format("<tr{}><td>{}</td><td class=\"val\">{}</td><td>{}</td><td>{}</td></tr>", cls, escaped(l.quantity),
                            escaped(l.value), escaped(l.limit), mark);
    }
    html += "</tbody></table>\n";
}

void append_plots(std::string& html, const CheckResult& r, std::size_t index) {
    if (r.plots.empty()) return;
    html += "<div class=\"plots\">\n";
    for (std::size_t p = 0; p < r.plots.size(); ++p) {
        SvgOptions options;
        options.id_prefix = fmt::format("p{}-{}", index, p);
        html += "<figure>";
        if (!r.plots[p].title.empty()) html += "<figcaption>" + escaped(r.plots[p].title) + "</figcaption>";
        html += render_svg(r.plots[p], options);
        if (!r.plots[p].note.empty()) html += "<p class=\"note\">" + escaped(r.plots[p].note) + "</p>";
        html += "</figure>\n";
    }
    html += "</div>\n";
}

void append_figures(std::string& html, const CheckResult& r) {
    if (r.figures.empty()) return;
    html += fmt::format("<details class=\"figs\"><summary>All {} figures</summary><dl class=\"figures\">", r.figures.size());
    for (const Figure& f : r.figures)
        html += fmt::format("<div><dt>{}</dt><dd title=\"{}\">{}</dd></div>", escaped(f.name),
                            escaped(std::isfinite(f.value) ? fmt::format("{}", f.value) : format_number(f.value)),
                            escaped(format_grouped(f.value)));
    html += "</dl></details>\n";
}

}  // namespace

std::vector<FamilyGroup> family_groups(const RunResult& run) {
    std::vector<FamilyGroup> groups;
    std::map<std::string, std::size_t> at;
    for (std::size_t i = 0; i < run.results.size(); ++i) {
        const std::string family = family_of(run.results[i].case_name);
        auto [it, added] = at.try_emplace(family, groups.size());
        if (added) groups.push_back({family, {}});
        groups[it->second].rows.push_back(i);
    }
    for (FamilyGroup& g : groups)
        std::sort(g.rows.begin(), g.rows.end(), [&](std::size_t a, std::size_t b) { return key_of(run, a) < key_of(run, b); });
    // A family stands where its first (worst) row would stand among all rows.
    std::stable_sort(groups.begin(), groups.end(), [&](const FamilyGroup& a, const FamilyGroup& b) {
        return key_of(run, a.rows.front()) < key_of(run, b.rows.front());
    });
    return groups;
}

std::string row_body(const RunResult& run, std::size_t index) {
    const CheckResult& r = run.results[index];
    std::string html;
    if (!r.message.empty()) html += "<p class=\"message\">" + escaped(r.message) + "</p>\n";
    append_facts(html, r);
    if (!r.rerun_command.empty())
        html += "<div class=\"rerun\"><span class=\"note\">Rerun just this check:</span><pre><code>" + escaped(r.rerun_command) +
                "</code></pre></div>\n";
    append_judged(html, r);
    append_plots(html, r, index);
    for (const Table& t : r.tables) append_evidence_table(html, t);
    append_figures(html, r);
    return html;
}

}  // namespace warpcheck::html
