#include "reports/terminal_table.h"

#include <algorithm>
#include <map>
#include <ostream>
#include <vector>

#include <fmt/format.h>

namespace warpcheck {
namespace {

std::string verdict_cell(Verdict v, bool color) {
    const std::string text = fmt::format("{:<5}", to_string(v));
    if (!color) return text;
    const char* code = v == Verdict::Pass ? "32" : v == Verdict::Fail ? "1;31" : v == Verdict::Error ? "1;35" : "2";
    return fmt::format("\033[{}m{}\033[0m", code, text);
}

// The length of the valid UTF-8 sequence at the start of `text` that is not a
// control character, or 0.
std::size_t printable_sequence(std::string_view text) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(0);
    if (lead >= 0x20 && lead < 0x7F) return 1;
    const std::size_t length = lead >= 0xC2 && lead <= 0xDF ? 2 : lead >= 0xE0 && lead <= 0xEF ? 3
                               : lead >= 0xF0 && lead <= 0xF4                 ? 4
                                                                              : 0;
    if (length == 0 || text.size() < length) return 0;
    for (std::size_t i = 1; i < length; ++i)
        if ((byte(i) & 0xC0) != 0x80) return 0;
    if (lead == 0xC2 && byte(1) < 0xA0) return 0;             // U+0080..U+009F: C1 controls (CSI is U+009B)
    if (lead == 0xE0 && byte(1) < 0xA0) return 0;             // overlong
    if (lead == 0xED && byte(1) >= 0xA0) return 0;            // UTF-16 surrogates
    if (lead == 0xF0 && byte(1) < 0x90) return 0;             // overlong
    if (lead == 0xF4 && byte(1) >= 0x90) return 0;            // beyond U+10FFFF
    return length;
}

}  // namespace

std::string terminal_text(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    while (!text.empty()) {
        std::size_t n = printable_sequence(text);
        if (n > 0) {
            out.append(text.substr(0, n));
        } else {
            n = 1;
            out += fmt::format("\\x{:02x}", static_cast<unsigned char>(text.front()));
        }
        text.remove_prefix(n);
    }
    return out;
}

void print_summary(const RunResult& run, std::ostream& out) {
    const auto& i = run.info;
    const int not_applicable = run.count(Verdict::NotApplicable);
    out << fmt::format("{} checks: {} passed, {} failed, {} errors{} in {:.1f} s  (seed {}, {} samples, {} threads)\n",
                       run.results.size(), run.count(Verdict::Pass), run.count(Verdict::Fail),
                       run.count(Verdict::Error),
                       not_applicable > 0 ? fmt::format(", {} not applicable", not_applicable) : std::string(),
                       i.wall_seconds, i.seed, i.samples, i.threads);
    if (i.statistical_tests > 0)
        out << fmt::format("Statistical tests: {} at per-test level {:.3g} (family-wise alpha {} with Sidak correction)\n",
                           i.statistical_tests, i.per_test_alpha, i.family_alpha);
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
        out << fmt::format("  {:>9.3f} s  {} {}{}\n", r->seconds, terminal_text(r->check_name),
                           terminal_text(r->case_name), parts.empty() ? "" : "  (" + terminal_text(parts) + ")");
    }
}

void print_table(const RunResult& run, std::ostream& out, const TableStyle& style) {
    std::size_t case_width = 4, check_width = 5;
    for (const auto& r : run.results) {
        case_width = std::max(case_width, terminal_text(r.case_name).size());
        check_width = std::max(check_width, terminal_text(r.check_name).size());
    }
    case_width = std::min<std::size_t>(case_width, 64);
    out << fmt::format("{:<5}  {:<{}}  {:<{}}  {}\n", "", "check", check_width, "case", case_width, "key figure");
    for (const auto& r : run.results) {
        if (style.failures_only && (r.verdict == Verdict::Pass || r.verdict == Verdict::NotApplicable)) continue;
        out << fmt::format("{}  {:<{}}  {:<{}}  {}\n", verdict_cell(r.verdict, style.color),
                           terminal_text(r.check_name), check_width, terminal_text(r.case_name), case_width,
                           terminal_text(r.summary));
    }
    bool header = false;
    for (const auto& r : run.results) {
        if (r.verdict == Verdict::Pass || r.verdict == Verdict::NotApplicable) continue;
        if (!header) {
            out << "\nWhat failed, and how to rerun it:\n";
            header = true;
        }
        out << fmt::format("  {} {} {}: {}\n    rerun: {}\n", to_string(r.verdict), terminal_text(r.check_name),
                           terminal_text(r.case_name), terminal_text(r.message),
                           terminal_text(r.rerun_command));
    }
    if (style.timings) print_timings(run, out);
    out << "\n";
    print_summary(run, out);
}

}  // namespace warpcheck
