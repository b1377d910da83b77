// A check's judgement, written into its result (CheckResult::judged): each
// judged quantity with its value, the limit it is held to and whether it is
// within. A check states its rules here, beside its verdict
// (Check::judged_rules): the figures it judges, its p-values' lines; the
// runner applies them once the run's level is settled (record_judgement), and
// every report draws the lines without restating a rule.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "reports/result.h"

namespace warpcheck {

/// How a figure is judged.
enum class FigureRule {
    Zero,         ///< a count that must be 0
    AtMost,       ///< at most the figure `limit`
    WithinOfOne,  ///< |value - 1| at most the figure `limit`
    Counted,      ///< reported, not judged (an excuse or a note)
};

/// One figure a check judges (or reports beside its verdict), in its own words.
struct JudgedFigure {
    const char* figure;
    const char* quantity;
    FigureRule rule;
    const char* limit = "";
};

/// Appends the lines of the tests a row's p-value combines, each at its
/// share of the per-test level `level`.
using PValueLines = void (*)(const CheckResult& r, double level, std::vector<JudgedQuantity>& out);
/// Appends the lines of rules that compare figures with each other.
using BoundLines = void (*)(const CheckResult& r, std::vector<JudgedQuantity>& out);

/// Marks in a row's plots the quantity judged and its limit, and says under
/// each plot what they mean (Plot::limits, highlights, cells, scale_marks,
/// note), from the row's figures, plots and tables; r.level is set when the
/// row has one.
using PlotMarks = void (*)(CheckResult& r);

/// What a check judges (Check::judged_rules).
struct JudgedRules {
    std::vector<JudgedFigure> figures{};
    PValueLines p_values = nullptr;    ///< none: the p-value's own line alone
    std::string p_value = "p-value";   ///< what the row's p-value is, as its line names it
    BoundLines bounds = nullptr;
    PlotMarks marks = nullptr;         ///< none: the plots as the check drew them
};

/// The lines of `r` by `rules`: the p-values (at r.level; "no level applied"
/// without one), the bounds, each declared figure that `r` has, then every
/// `*_over_tolerance` figure and every figure X beside an X_tolerance that no
/// rule took (the terminal table's margin). A NaN value is never within.
std::vector<JudgedQuantity> judged_lines(const CheckResult& r, const JudgedRules& rules);

/// Writes r.judged by `rules` on a row that passed or failed, once its level
/// is settled, and its plots' marks (rules.marks); an error or n/a row judged
/// nothing and gets no lines.
void record_judgement(CheckResult& r, const JudgedRules& rules);

/// Under --strict (the row's figure "strict" is 1): `figure` must be 0,
/// where by default it is an excuse counted beside the verdict.
void strict_zero_line(const CheckResult& r, const char* figure, const char* quantity, std::vector<JudgedQuantity>& out);

/// `line`, a size held under `limit`, with its margin: size / limit (none
/// where the limit is 0, an exact rule, or not finite). A NaN size keeps a
/// NaN margin, as its line is never within.
JudgedQuantity with_margin(JudgedQuantity line, double size, double limit);
/// A p-value's line: within where p >= limit (NaN is below every limit),
/// with its margin p / limit.
JudgedQuantity p_line(std::string quantity, double p, double limit, const std::string& limit_note);
/// A value as the lines print it: integers grouped, others to 3 digits.
std::string judged_number(double v);
/// The lines of two or more tests of one row, each at an equal share of the
/// level (Bonferroni): (figure, quantity) of each; tests without their figure
/// (or NaN) are left out, and nothing is added with fewer than two.
void shared_p_lines(const CheckResult& r, double level, std::vector<JudgedQuantity>& out,
                    std::vector<std::pair<const char*, const char*>> tests);

}  // namespace warpcheck
