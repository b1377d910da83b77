#include "reports/terminal_table.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <ostream>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "reports/text.h"

namespace warpcheck {
namespace {

constexpr std::size_t kVerdictWidth = 5;
constexpr std::size_t kMinCaseWidth = 24;  ///< a narrow table still shows this much of a case name
constexpr std::size_t kMinKeyWidth = 16;   ///< ... and this much of the key figure

std::string verdict_cell(const CheckResult& r, bool color) {
    const Verdict v = r.verdict;
    const std::string text = fmt::format("{:<{}}", verdict_word(r), kVerdictWidth);
    if (!color) return text;
    const bool weak = v == Verdict::Pass && !r.weak.empty();
    const char* code = weak              ? "33"
                       : v == Verdict::Pass ? "32"
                       : v == Verdict::Fail ? "1;31"
                       : v == Verdict::Error ? "1;35"
                                             : "2";
    return fmt::format("\033[{}m{}\033[0m", code, text);
}

bool shown(const CheckResult& r, const TableStyle& style) {
    return !style.failures_only || r.verdict == Verdict::Fail || r.verdict == Verdict::Error;
}

/// A ratio in few characters: "390", "0.53", "2e+05" -> "2e5".
std::string compact(double v) {
    if (std::isnan(v)) return "NaN";
    std::string text = v >= 1.0 && v < 1e4 ? fmt::format("{:.0f}", v) : fmt::format("{:.2g}", v);
    for (const std::string_view noise : {"e+0", "e+", "e-0"}) {
        const std::size_t at = text.find(noise);
        if (at != std::string::npos) text.replace(at, noise.size(), noise == "e-0" ? "e-" : "e");
    }
    return text;
}

void keep_largest(RowMargin& m, double fraction, const std::string& figure) {
    if (!std::isnan(fraction) && (!m.of_tolerance || fraction > *m.of_tolerance)) {
        m.of_tolerance = fraction;
        m.tolerance_figure = figure;
    }
}

/// The margin cell of a row: a row that did not pass shows its margin only
/// when that is what failed it (past its limit), so that a row failed for
/// another reason (an inverse outside [0,1)) does not read as "within".
std::string margin_cell(const CheckResult& r) {
    const RowMargin m = row_margin(r);
    if (r.verdict == Verdict::Pass) return margin_text(m);
    const bool past = (m.p_over_level && !(*m.p_over_level >= 1.0)) || (m.of_tolerance && *m.of_tolerance > 1.0);
    return past ? margin_text(m) : "";
}

struct Widths {
    std::size_t check = 5, case_name = 4, margin = 6, key = 0;  ///< key 0: no limit
};

/// The columns of a case name's parameters, "[...]" (0 without them).
std::size_t params_width(const std::string& name) {
    const std::size_t bracket = name.find('[');
    return bracket == std::string::npos ? 0 : display_width(std::string_view(name).substr(bracket));
}

Widths column_widths(const RunResult& run, const TableStyle& style) {
    Widths w;
    std::size_t longest_case = 4, longest_params = 0;
    for (const auto& r : run.results) {
        if (!shown(r, style)) continue;
        const std::string name = printable(r.case_name);
        w.check = std::max(w.check, display_width(r.check_name));
        longest_case = std::max(longest_case, display_width(name));
        longest_params = std::max(longest_params, params_width(name));
        w.margin = std::max(w.margin, margin_cell(r).size());
    }
    w.case_name = std::min<std::size_t>(longest_case, 64);
    if (style.width == 0) return w;
    // verdict, check, case, margin, key figure: four gaps of two columns.
    const std::size_t fixed = kVerdictWidth + w.check + w.margin + 8;
    const std::size_t room = style.width > fixed ? style.width - fixed : 0;
    // The case takes 45% of what is left, and more where a case's parameters
    // need it, which tell a family's rows apart and are never cut (the family
    // is: to a lone "…" at the least); the key figure takes the rest, which it
    // fills up to its end (a table only wider than `width` where even
    // kMinKeyWidth columns of it do not fit).
    const std::size_t whole_params = std::min(longest_case, longest_params + 1);
    w.case_name = std::max(std::min(w.case_name, std::max(kMinCaseWidth, room * 45 / 100)), whole_params);
    w.key = std::max(kMinKeyWidth, room > w.case_name ? room - w.case_name : 0);
    return w;
}

void print_rows(const RunResult& run, std::ostream& out, const TableStyle& style) {
    const Widths w = column_widths(run, style);
    out << fmt::format("{:<{}}  {:<{}}  {:<{}}  {:<{}}  {}\n", "", kVerdictWidth, "check", w.check, "case", w.case_name,
                       "margin", w.margin, "key figure");
    for (const auto& r : run.results) {
        if (!shown(r, style)) continue;
        const std::string name = fit_case_name(printable(r.case_name), w.case_name);
        const std::string key = printable(r.summary);
        out << fmt::format("{}  {:<{}}  {}{}  {:<{}}  {}\n", verdict_cell(r, style.color), r.check_name,
                           w.check, name, std::string(w.case_name - std::min(w.case_name, display_width(name)), ' '),
                           margin_cell(r), w.margin, w.key ? fit_columns(key, w.key) : key);
    }
}

/// The line that stands for an empty table of failures.
void print_no_failures(const RunResult& run, std::ostream& out) {
    const int not_applicable = run.count(Verdict::NotApplicable);
    const std::size_t applicable = run.results.size() - static_cast<std::size_t>(not_applicable);
    out << fmt::format("No failures: all {} checks that ran passed{}.\n", applicable,
                       not_applicable > 0 ? fmt::format(" ({} not applicable)", not_applicable) : std::string());
}

void print_failures(const RunResult& run, std::ostream& out) {
    bool header = false;
    for (const auto& r : run.results) {
        if (r.verdict == Verdict::Pass || r.verdict == Verdict::NotApplicable) continue;
        if (!header) {
            out << "\nWhat failed, and how to rerun it:\n";
            header = true;
        }
        out << fmt::format("  {} {} {}: {}\n    rerun: {}\n", to_string(r.verdict), r.check_name,
                           printable(r.case_name), printable(r.message), printable(r.rerun_command));
    }
}

/// `text` cut in the middle to `columns`: a family's end (_visible, _normals)
/// tells families apart as much as its start.
std::string fit_middle(const std::string& text, std::size_t columns) {
    const std::size_t width = display_width(text);
    if (width <= columns || columns < 3) return fit_columns(text, columns);
    const std::size_t head = (columns - 1) / 2, tail = columns - 1 - head;
    std::size_t seen = 0, head_end = 0, tail_start = text.size();
    for (std::size_t i = 0; i < text.size(); ++i) {
        if ((static_cast<unsigned char>(text[i]) & 0xC0) == 0x80) continue;
        if (seen == head) head_end = i;
        if (seen == width - tail) tail_start = i;
        ++seen;
    }
    return text.substr(0, head_end) + "\xE2\x80\xA6" + text.substr(tail_start);
}

std::string family_of(const std::string& case_name) { return case_name.substr(0, case_name.find('[')); }

bool several_families(const RunResult& run) {
    return std::any_of(run.results.begin(), run.results.end(), [&](const CheckResult& r) {
        return family_of(r.case_name) != family_of(run.results.front().case_name);
    });
}

}  // namespace

RowMargin row_margin(const CheckResult& r) {
    RowMargin m;
    if (r.p_value && r.level && *r.level > 0.0) m.p_over_level = *r.p_value / *r.level;
    for (const JudgedQuantity& j : r.judged)
        if (j.margin_kind == JudgedQuantity::Margin::OfLimit) keep_largest(m, j.margin, j.quantity);
    return m;
}

std::string margin_text(const RowMargin& m) {
    // Far from the limit, how far no longer matters: the column stays quiet
    // and the rows near a limit stand out.
    if (m.p_over_level) return *m.p_over_level >= 1000.0 ? ">1000x level" : compact(*m.p_over_level) + "x level";
    if (m.of_tolerance) return *m.of_tolerance < 0.01 ? "<0.01 of tol" : compact(*m.of_tolerance) + " of tol";
    return "";
}

std::string fit_case_name(const std::string& name, std::size_t columns) {
    if (display_width(name) <= columns) return name;
    const std::size_t bracket = name.find('[');
    const std::size_t params = params_width(name);
    // The parameters whole, the family cut in its middle to what is left of
    // the columns (a lone "…" at the least).
    if (bracket != std::string::npos && params + 1 <= columns)
        return fit_middle(name.substr(0, bracket), columns - params) + name.substr(bracket);
    return fit_columns(name, columns);
}

void print_summary(const RunResult& run, std::ostream& out) {
    const auto& i = run.info;
    // The checks that ran, as the progress display counts them; the n/a rows apart.
    const int not_applicable = run.count(Verdict::NotApplicable);
    const std::size_t ran = run.results.size() - static_cast<std::size_t>(not_applicable);
    const auto weak = std::count_if(run.results.begin(), run.results.end(), [](const CheckResult& r) {
        return r.verdict == Verdict::Pass && !r.weak.empty();
    });
    out << fmt::format("{} checks: {} passed{}, {} failed, {} errors{} in {:.1f} s  (seed {}, {} samples, {} threads)\n",
                       ran, run.count(Verdict::Pass),
                       weak > 0 ? fmt::format(" ({} weak: could not see a 5% tilt)", weak) : std::string(),
                       run.count(Verdict::Fail), run.count(Verdict::Error),
                       not_applicable > 0 ? fmt::format("; {} n/a, not run", not_applicable) : std::string(),
                       i.wall_seconds, i.seed, i.samples, i.threads);
    if (i.statistical_tests > 0)
        out << fmt::format("Statistical tests: {} at per-test level {:.3g} (family-wise alpha {} with Sidak correction)\n",
                           i.statistical_tests, i.per_test_alpha, i.family_alpha);
}

void print_family_summary(const RunResult& run, std::ostream& out, bool failures_only) {
    struct Counts {
        std::vector<std::string> cases;
        std::array<int, 4> verdicts{};  // Pass, Fail, Error, NotApplicable
    };
    std::vector<std::string> order;
    std::map<std::string, Counts> families;
    for (const auto& r : run.results) {
        const std::string family = printable(family_of(r.case_name));
        auto [it, added] = families.try_emplace(family);
        if (added) order.push_back(family);
        if (std::find(it->second.cases.begin(), it->second.cases.end(), r.case_name) == it->second.cases.end())
            it->second.cases.push_back(r.case_name);
        ++it->second.verdicts[static_cast<std::size_t>(r.verdict)];
    }
    std::size_t width = 6;
    for (const auto& f : order) width = std::max(width, display_width(f));
    width = std::min<std::size_t>(width, 48);
    out << fmt::format("\nBy family:\n  {:<{}}  {:>5}  {:>5}  {:>5}  {:>5}  {:>5}\n", "family", width, "cases", "pass",
                       "FAIL", "ERROR", "n/a");
    const auto cell = [](int n) { return n == 0 ? std::string("-") : std::to_string(n); };
    for (const auto& name : order) {
        const Counts& c = families[name];
        if (failures_only && c.verdicts[1] + c.verdicts[2] == 0) continue;
        out << fmt::format("  {}{}  {:>5}  {:>5}  {:>5}  {:>5}  {:>5}\n", fit_columns(name, width),
                           std::string(width - std::min(width, display_width(fit_columns(name, width))), ' '),
                           c.cases.size(), cell(c.verdicts[0]), cell(c.verdicts[1]), cell(c.verdicts[2]),
                           cell(c.verdicts[3]));
    }
}

void print_weakest(const RunResult& run, std::ostream& out, std::size_t count, std::size_t width) {
    struct Entry {
        double key;
        const CheckResult* row;
        std::string margin, figure;
    };
    std::vector<Entry> by_p, by_tolerance;
    for (const auto& r : run.results) {
        if (r.verdict != Verdict::Pass) continue;
        const RowMargin m = row_margin(r);
        if (m.p_over_level) by_p.push_back({*m.p_over_level, &r, compact(*m.p_over_level) + "x level", "p-value"});
        if (m.of_tolerance)
            by_tolerance.push_back({-*m.of_tolerance, &r, compact(*m.of_tolerance) + " of tol", m.tolerance_figure});
    }
    if (by_p.empty() && by_tolerance.empty()) return;
    // (Within 100 columns, as the rows are.)
    out << "\nClosest to their limits, of the passing rows (p-value / per-test level; error / tolerance):\n";
    std::size_t margin_width = 0, check_width = 0;
    for (auto* list : {&by_p, &by_tolerance}) {
        std::stable_sort(list->begin(), list->end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
        list->resize(std::min(list->size(), count));
        for (const Entry& e : *list) {
            margin_width = std::max(margin_width, e.margin.size());
            check_width = std::max(check_width, e.row->check_name.size());
        }
    }
    for (auto* list : {&by_p, &by_tolerance})
        for (const Entry& e : *list) {
            const std::string line = fmt::format("  {:<{}}  {:<{}}  {}  ({})", e.margin, margin_width, e.row->check_name,
                                                 check_width, printable(e.row->case_name), e.figure);
            out << (width ? fit_columns(line, width) : line) << "\n";
        }
}

/// The passes that could not have seen their check's stated effect, each with what it could not see.
void print_weak(const RunResult& run, std::ostream& out, std::size_t width) {
    bool header = false;
    for (const auto& r : run.results) {
        if (r.verdict != Verdict::Pass || r.weak.empty()) continue;
        if (!header) {
            out << "\nWeak: passes that could not have seen a 5% tilt (not failures; more samples or finer cells "
                   "would):\n";
            header = true;
        }
        const std::string line =
            fmt::format("  {} {}: {}", r.check_name, printable(r.case_name), printable(r.weak));
        out << (width ? fit_columns(line, width) : line) << "\n";
    }
}

void print_timings(const RunResult& run, std::ostream& out, std::size_t slowest) {
    double total = 0.0;
    std::map<std::string, std::pair<double, int>> by_check;
    for (const auto& r : run.results) {
        total += r.seconds;
        by_check[r.check_name].first += r.seconds;
        ++by_check[r.check_name].second;
    }
    std::vector<std::pair<std::string, std::pair<double, int>>> checks(by_check.begin(), by_check.end());
    std::stable_sort(checks.begin(), checks.end(),
                     [](const auto& x, const auto& y) { return x.second.first > y.second.first; });
    out << fmt::format("\nWhere the time went ({:.1f} s of check time over {} rows, {:.1f} s wall):\n", total,
                       run.results.size(), run.info.wall_seconds);
    for (const auto& [name, t] : checks)
        out << fmt::format("  {:<22} {:>9.2f} s  {:>5.1f}%  {} rows\n", name, t.first,
                           total > 0 ? 100.0 * t.first / total : 0.0, t.second);
    std::vector<const CheckResult*> rows;
    for (const auto& r : run.results) rows.push_back(&r);
    std::stable_sort(rows.begin(), rows.end(), [](const auto* x, const auto* y) { return x->seconds > y->seconds; });
    rows.resize(std::min(rows.size(), slowest));
    out << "Slowest rows, with the parts of their compute:\n";
    for (const CheckResult* r : rows) {
        std::string parts;
        for (const PhaseTime& p : r->phases) parts += fmt::format("{}{} {:.3f} s", parts.empty() ? "" : ", ", p.phase, p.seconds);
        out << fmt::format("  {:>9.3f} s  {} {}{}\n", r->seconds, printable(r->check_name), printable(r->case_name),
                           parts.empty() ? "" : "  (" + parts + ")");
    }
}

void print_table(const RunResult& run, std::ostream& out, const TableStyle& style) {
    const bool any_shown = std::any_of(run.results.begin(), run.results.end(),
                                       [&](const CheckResult& r) { return shown(r, style); });
    if (any_shown) print_rows(run, out, style);
    else if (style.failures_only) print_no_failures(run, out);
    if (style.families && (any_shown || !style.failures_only) && several_families(run))
        print_family_summary(run, out, style.failures_only);
    if (style.weakest > 0 && !style.failures_only) print_weakest(run, out, style.weakest, style.width);
    if (!style.failures_only) print_weak(run, out, style.width);
    print_failures(run, out);
    if (style.timings) print_timings(run, out);
    out << "\n";
    print_summary(run, out);
}

}  // namespace warpcheck
