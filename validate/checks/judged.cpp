// The judged lines of a row from its check's rules (validate/checks/judged.h).
#include "validate/checks/judged.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "reports/text.h"

namespace warpcheck {
namespace {

using State = JudgedQuantity::State;

std::optional<JudgedQuantity> figure_line(const CheckResult& r, const JudgedFigure& s) {
    const auto value = r.figure(s.figure);
    if (!value) return std::nullopt;
    const auto limit = *s.limit ? r.figure(s.limit) : std::nullopt;
    switch (s.rule) {
        case FigureRule::Zero:
            return JudgedQuantity{s.quantity, judged_number(*value), "= 0", *value == 0.0 ? State::Within : State::Beyond};
        case FigureRule::AtMost:
            // An exact rule (tolerance 0) is judged by its count of failures, not here.
            if (!limit || (*limit == 0.0 && std::string_view(s.limit) == "tolerance")) return std::nullopt;
            return with_margin({s.quantity, judged_number(*value), "\u2264 " + judged_number(*limit),
                                *value <= *limit ? State::Within : State::Beyond},
                               *value, *limit);
        case FigureRule::WithinOfOne:
            if (!limit) return std::nullopt;
            return with_margin({s.quantity, fmt::format("{:.9g}", *value), "|x \u2212 1| \u2264 " + judged_number(*limit),
                                std::abs(*value - 1.0) <= *limit ? State::Within : State::Beyond},
                               std::abs(*value - 1.0), *limit);
        case FigureRule::Counted:
            return JudgedQuantity{s.quantity, judged_number(*value), "counted", State::Reported};
    }
    return std::nullopt;
}

std::string probability(double p) { return std::isnan(p) ? "NaN" : format_probability(p); }

void p_value_lines(const CheckResult& r, const JudgedRules& rules, std::vector<JudgedQuantity>& out) {
    if (!r.p_value) return;
    if (!r.level) {
        out.push_back({rules.p_value, probability(*r.p_value), "no level applied", State::Reported});
        return;
    }
    if (rules.p_values) rules.p_values(r, *r.level, out);
    out.push_back(p_line(rules.p_value, *r.p_value, *r.level, " (per-test level)"));
}

/// Every `*_over_tolerance` figure and every `X` beside an `X_tolerance` that
/// no rule above took: the generic margin rules of the terminal table.
void tolerance_lines(const CheckResult& r, const std::set<std::string>& used, std::vector<JudgedQuantity>& out) {
    for (const Figure& f : r.figures) {
        if (used.count(f.name)) continue;
        if (f.name.ends_with("_over_tolerance")) {
            out.push_back(with_margin(
                {f.name, judged_number(f.value), "\u2264 1", f.value <= 1.0 ? State::Within : State::Beyond}, f.value, 1.0));
        } else if (const auto tol = r.figure(f.name + "_tolerance"); tol && !used.count(f.name + "_tolerance")) {
            const bool integral = f.name.ends_with("integral");
            const double error = integral ? std::abs(f.value - 1.0) : std::abs(f.value);
            out.push_back(with_margin({f.name, judged_number(f.value),
                                       (integral ? "|x \u2212 1| \u2264 " : "|x| \u2264 ") + judged_number(*tol),
                                       error <= *tol ? State::Within : State::Beyond},
                                      error, *tol));
        }
    }
}

}  // namespace

std::string judged_number(double v) {
    if (std::isfinite(v) && v == std::round(v) && std::abs(v) < 1e15) return format_grouped(v);
    return std::isfinite(v) ? fmt::format("{:.3g}", v) : format_number(v);
}

JudgedQuantity with_margin(JudgedQuantity line, double size, double limit) {
    // Over a limit of 0 (an exact rule) or a non-finite one, no fraction says how near.
    if (limit > 0.0 && std::isfinite(limit)) {
        line.margin_kind = JudgedQuantity::Margin::OfLimit;
        line.margin = size / limit;
    }
    return line;
}

JudgedQuantity p_line(std::string quantity, double p, double limit, const std::string& limit_note) {
    JudgedQuantity line{std::move(quantity), probability(p),
                        fmt::format("\u2265 {}{}", format_probability(limit), limit_note),
                        p >= limit ? State::Within : State::Beyond};
    if (limit > 0.0 && std::isfinite(limit)) {
        line.margin_kind = JudgedQuantity::Margin::POverLimit;
        line.margin = p / limit;
    }
    return line;
}

void strict_zero_line(const CheckResult& r, const char* figure, const char* quantity, std::vector<JudgedQuantity>& out) {
    const auto value = r.figure(figure);
    if (!value || r.figure("strict").value_or(0.0) == 0.0) return;
    out.push_back({std::string(quantity) + " (--strict allows none)", judged_number(*value), "= 0",
                   *value == 0.0 ? State::Within : State::Beyond});
}

void shared_p_lines(const CheckResult& r, double level, std::vector<JudgedQuantity>& out,
                    std::vector<std::pair<const char*, const char*>> tests) {
    std::erase_if(tests, [&](const auto& t) { return !r.figure(t.first) || std::isnan(*r.figure(t.first)); });
    if (tests.size() < 2) return;
    const double share = 1.0 / static_cast<double>(tests.size());
    for (const auto& [figure, quantity] : tests)
        out.push_back(p_line(quantity, *r.figure(figure), share * level, fmt::format(" (level / {})", tests.size())));
}

std::vector<JudgedQuantity> judged_lines(const CheckResult& r, const JudgedRules& rules) {
    std::vector<JudgedQuantity> out;
    p_value_lines(r, rules, out);
    if (rules.bounds) rules.bounds(r, out);
    std::set<std::string> used;
    for (const JudgedFigure& s : rules.figures) {
        if (auto line = figure_line(r, s)) {
            out.push_back(std::move(*line));
            used.insert(s.figure);
            if (*s.limit) used.insert(s.limit);
        }
    }
    tolerance_lines(r, used, out);
    return out;
}

void record_judgement(CheckResult& r, const JudgedRules& rules) {
    r.judged.clear();
    if (r.verdict != Verdict::Pass && r.verdict != Verdict::Fail) return;
    r.judged = judged_lines(r, rules);
    if (rules.marks) rules.marks(r);
}

}  // namespace warpcheck
