// The JUnit XML report, for CI systems: one <testsuite> per check ("chi2",
// "roundtrip", ...) in the order checks first appear, one <testcase> per
// (case, check) row; <failure> for a failed check, <error> for one that could
// not run, with the message, the key figures and the rerun command; <skipped>
// for a check that does not apply to the case (a round trip without an inverse).
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "reports/atomic_file.h"
#include "reports/outputs.h"
#include "reports/render.h"
#include "reports/text.h"

namespace warpcheck {
namespace {

std::string attr(std::string_view text) { return escaped(text); }

std::string seconds(double s) { return fmt::format("{:.3f}", std::isfinite(s) && s > 0.0 ? s : 0.0); }

/// The text inside <failure> or <error>: what a CI page shows when the row is
/// opened, enough to start debugging without the HTML report.
std::string failure_text(const CheckResult& r) {
    std::string text;
    if (!r.message.empty()) text += r.message + "\n";
    if (!r.summary.empty()) text += "summary: " + r.summary + "\n";
    if (r.p_value) text += fmt::format("p-value: {}{}\n", format_probability(*r.p_value),
                                       r.level ? " (level " + format_probability(*r.level) + ")" : "");
    for (const Figure& f : r.figures) text += fmt::format("{}: {}\n", f.name, format_number(f.value));
    if (!r.rerun_command.empty()) text += "rerun: " + r.rerun_command + "\n";
    return text;
}

}  // namespace

std::string render_junit(const RunResult& run) {
    const RunInfo& info = run.info;
    std::vector<std::string> checks;
    std::map<std::string, std::vector<const CheckResult*>> by_check;
    for (const CheckResult& r : run.results) {
        if (!by_check.count(r.check_name)) checks.push_back(r.check_name);
        by_check[r.check_name].push_back(&r);
    }

    std::string xml = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    xml += fmt::format("<testsuites name=\"warpcheck\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"{}\" "
                       "time=\"{}\"{}>\n",
                       run.results.size(), run.count(Verdict::Fail), run.count(Verdict::Error),
                       run.count(Verdict::NotApplicable), seconds(info.wall_seconds),
                       info.started_at.empty() ? "" : " timestamp=\"" + attr(info.started_at) + "\"");
    for (const std::string& check : checks) {
        const auto& rows = by_check[check];
        int failures = 0, errors = 0, skipped = 0;
        double time = 0.0;
        for (const CheckResult* r : rows) {
            failures += r->verdict == Verdict::Fail;
            errors += r->verdict == Verdict::Error;
            skipped += r->verdict == Verdict::NotApplicable;
            if (std::isfinite(r->seconds)) time += r->seconds;
        }
        const std::string suite = "warpcheck." + check;
        xml += fmt::format("  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"{}\" time=\"{}\"{}{}>\n",
                           attr(suite), rows.size(), failures, errors, skipped, seconds(time),
                           info.started_at.empty() ? "" : " timestamp=\"" + attr(info.started_at) + "\"",
                           info.machine.empty() ? "" : " hostname=\"" + attr(info.machine) + "\"");
        xml += "    <properties>\n";
        const auto property = [&](std::string_view name, const std::string& value) {
            xml += fmt::format("      <property name=\"{}\" value=\"{}\"/>\n", attr(name), attr(value));
        };
        property("seed", std::to_string(info.seed));
        property("samples", std::to_string(info.samples));
        property("family_alpha", format_probability(info.family_alpha));
        property("per_test_alpha", format_probability(info.per_test_alpha));
        property("statistical_tests", std::to_string(info.statistical_tests));
        if (!info.compiler.empty()) property("compiler", info.compiler);
        if (!info.command_line.empty()) property("command_line", info.command_line);
        xml += "    </properties>\n";
        for (const CheckResult* r : rows) {
            xml += fmt::format("    <testcase name=\"{}\" classname=\"{}\" time=\"{}\"", attr(r->case_name), attr(suite),
                               seconds(r->seconds));
            if (r->verdict == Verdict::Pass && r->summary.empty()) {
                xml += "/>\n";
                continue;
            }
            xml += ">\n";
            if (r->verdict == Verdict::NotApplicable) {
                xml += fmt::format("      <skipped message=\"{}\"/>\n", attr(r->summary));
            } else if (r->verdict != Verdict::Pass) {
                const char* element = r->verdict == Verdict::Fail ? "failure" : "error";
                const std::string message = r->message.empty() ? r->summary : r->message;
                xml += fmt::format("      <{0} message=\"{1}\" type=\"{2}\">{3}</{0}>\n", element, attr(message),
                                   attr(r->check_name), escaped(failure_text(*r)));
            }
            std::string out;
            if (!r->summary.empty()) out += r->summary + "\n";
            if (!r->rerun_command.empty()) out += "rerun: " + r->rerun_command + "\n";
            if (!out.empty()) xml += "      <system-out>" + escaped(out) + "</system-out>\n";
            xml += "    </testcase>\n";
        }
        xml += "  </testsuite>\n";
    }
    xml += "</testsuites>\n";
    return xml;
}

void write_junit_report(const RunResult& run, const std::string& path) {
    write_file_atomically(path, render_junit(run));
}

}  // namespace warpcheck
