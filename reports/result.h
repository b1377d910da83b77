// The result model: plain data that every check produces and every output format
// (terminal table, JSON, JUnit XML, HTML) is a view of. No behaviour lives here.
//
// Beside each type stands its description, `fields(visitor, value)`: every
// member with its name, in the order the JSON report writes them. The JSON
// writer, the `--merge` reader and the worker codec are all made from these
// (reports/result_json.h), so a new member is one line here, next to it,
// plus the schema (reports/schema); a member left out of its description fails
// the test ResultModel.DescriptionsCoverEveryMember. A visitor `v` offers:
//   v("name", member)                      one value: a number, string, bool, enum,
//                                          optional number, or a list or described type
//   v.group("name", [&](auto& g) {...})    a nested object of members
//   v.optional_group("name", present, fn)  one written only when `present`
//   v.named_numbers("name", list)          a list of (name, number) pairs written as
//                                          one object; each element describes itself
//                                          as v.entry(name, number)
#pragma once

#include <array>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace warpcheck {

/// T is the model type U, const or not: the descriptions serve writers and readers.
template <class T, class U>
concept Model = std::same_as<std::remove_const_t<T>, U>;

/// The names JSON and the codec give an enum's values, in the order of the
/// enumerators, and what one is called in an error message.
template <class Enum>
struct EnumNames;

enum class Verdict {
    Pass,   ///< the check ran and the warp agrees with itself
    Fail,   ///< the check ran and found a disagreement
    Error,  ///< the check could not run (the warp threw, timed out, ...): the message says why
    /// The check does not apply to this case because the case lacks a part it
    /// tests (a warp without an inverse has no round trip): shown, never run,
    /// never a failure, and outside the multiple-testing family.
    NotApplicable,
};

constexpr std::string_view to_string(Verdict v) {
    switch (v) {
        case Verdict::Pass: return "pass";
        case Verdict::Fail: return "FAIL";
        case Verdict::Error: return "ERROR";
        case Verdict::NotApplicable: return "n/a";
    }
    return "?";
}

template <>
struct EnumNames<Verdict> {
    static constexpr std::string_view noun = "verdict";
    static constexpr std::array<std::string_view, 4> names{"pass", "fail", "error", "not_applicable"};
};

/// A named number, e.g. {"p_value", 0.43} or {"max_error", 1.2e-7}.
struct Figure {
    std::string name;
    double value = 0.0;
};

template <class V, Model<Figure> T>
void fields(V& v, T& f) {
    v.entry(f.name, f.value);
}

/// One curve or bar series of a plot.
struct Series {
    std::string label;
    std::vector<double> x;
    std::vector<double> y;
    /// An interval around each y (a confidence interval), drawn as an error
    /// bar from y_low to y_high: both as long as y, or both empty for none.
    std::vector<double> y_low{};
    std::vector<double> y_high{};
};

template <class V, Model<Series> T>
void fields(V& v, T& s) {
    v("label", s.label);
    v("x", s.x);
    v("y", s.y);
    v("y_low", s.y_low);
    v("y_high", s.y_high);
}

/// A 2D grid of values over [x_min, x_max] x [y_min, y_max]; values are row-major
/// with row 0 at y_min. NaN marks a cell without a value (e.g. pooled away).
struct Heatmap {
    std::string label;
    int rows = 0;
    int cols = 0;
    double x_min = 0.0, x_max = 1.0, y_min = 0.0, y_max = 1.0;
    std::vector<double> values;

    /// How values map to colours. The heatmaps of one plot that use the same kind
    /// of scale share one scale, so that e.g. observed and expected counts compare
    /// by eye; a diverging scale is symmetric about 0.
    enum class ColorScale {
        Auto,        ///< Diverging if this heatmap's values take both signs, else Sequential
        Sequential,  ///< low to high: counts, densities
        Diverging,   ///< about 0: residuals, differences
    };
    ColorScale color_scale = ColorScale::Auto;
    /// The colour scale reaches at least this far from 0 (both ways when
    /// diverging), however small the values: with 4 on a map of residuals in
    /// standard deviations, noise stays pale and a real deviation stands out.
    /// Larger values still widen the scale. 0: fit the scale to the values.
    double min_color_limit = 0.0;
};

template <>
struct EnumNames<Heatmap::ColorScale> {
    static constexpr std::string_view noun = "colour scale";
    static constexpr std::array<std::string_view, 3> names{"auto", "sequential", "diverging"};
};

template <class V, Model<Heatmap> T>
void fields(V& v, T& h) {
    v("label", h.label);
    v("rows", h.rows);
    v("cols", h.cols);
    v("x_min", h.x_min);
    v("x_max", h.x_max);
    v("y_min", h.y_min);
    v("y_max", h.y_max);
    v("color_scale", h.color_scale);
    v("min_color_limit", h.min_color_limit);
    v("values", h.values);
}

/// A limit drawn across an x-y plot: a vertical line at x = value, or a
/// horizontal one at y = value, dashed in the colour of failures and labelled
/// (e.g. "tolerance 1.5e-05"). The axis widens to show it.
struct LimitLine {
    bool vertical = true;
    double value = 0.0;
    std::string label;
};

template <class V, Model<LimitLine> T>
void fields(V& v, T& l) {
    v("vertical", l.vertical);
    v("value", l.value);
    v("label", l.label);
}

/// A point of an x-y plot ringed and labelled: a float that failed, the most
/// biased float, where a statistic takes its value. The axes widen to show it.
struct Highlight {
    double x = 0.0, y = 0.0;
    std::string label;
};

template <class V, Model<Highlight> T>
void fields(V& v, T& h) {
    v("x", h.x);
    v("y", h.y);
    v("label", h.label);
}

/// A cell of one heatmap of a plot ringed and labelled, e.g. the cell with the
/// largest residual. Row 0 is at y_min, as in Heatmap::values.
struct CellHighlight {
    std::size_t heatmap = 0;
    int row = 0, col = 0;
    std::string label;
};

template <class V, Model<CellHighlight> T>
void fields(V& v, T& c) {
    v("heatmap", c.heatmap);
    v("row", c.row);
    v("col", c.col);
    v("label", c.label);
}

/// A value marked on the colour bar of a heatmap's scale (both signs on a
/// diverging one), e.g. the residual at which one cell alone fails. The scale
/// widens to show it.
struct ScaleMark {
    std::size_t heatmap = 0;
    double value = 0.0;
    std::string label;
};

template <class V, Model<ScaleMark> T>
void fields(V& v, T& m) {
    v("heatmap", m.heatmap);
    v("value", m.value);
    v("label", m.label);
}

struct Plot {
    enum class Kind { Lines, Bars, Points, Heatmaps };
    Kind kind = Kind::Lines;
    std::string title;
    std::string x_label;
    std::string y_label;
    bool log_x = false;
    bool log_y = false;
    std::vector<Series> series;     ///< Lines, Bars, Points
    std::vector<Heatmap> heatmaps;  ///< Heatmaps: shown side by side (e.g. observed, expected, residual)
    /// What the check marks in its plot, so that it shows the quantity judged
    /// and its limit (written by the check's rules, validate/checks/judged.h,
    /// once the run's level is settled; reports draw them whatever the check):
    /// limit lines, ringed points and cells, marks on a colour scale, and a
    /// sentence saying what is judged and what the marks mean.
    std::vector<LimitLine> limits{};
    std::vector<Highlight> highlights{};
    std::vector<CellHighlight> cells{};
    std::vector<ScaleMark> scale_marks{};
    std::string note{};
    bool marked() const {
        return !limits.empty() || !highlights.empty() || !cells.empty() || !scale_marks.empty() || !note.empty();
    }
};

template <>
struct EnumNames<Plot::Kind> {
    static constexpr std::string_view noun = "plot kind";
    static constexpr std::array<std::string_view, 4> names{"lines", "bars", "points", "heatmaps"};
};

template <class V, Model<Plot> T>
void fields(V& v, T& p) {
    v("kind", p.kind);
    v("title", p.title);
    v("x_label", p.x_label);
    v("y_label", p.y_label);
    v("log_x", p.log_x);
    v("log_y", p.log_y);
    v("series", p.series);
    v("heatmaps", p.heatmaps);
    v.optional_group("marks", p.marked(), [&](auto& g) {
        g("limits", p.limits);
        g("highlights", p.highlights);
        g("cells", p.cells);
        g("scale_marks", p.scale_marks);
        g("note", p.note);
    });
}

/// A small table of evidence, e.g. the worst inputs of a round trip.
struct Table {
    std::string title;
    std::vector<std::string> columns;
    std::vector<std::vector<std::string>> rows;
};

template <class V, Model<Table> T>
void fields(V& v, T& t) {
    v("title", t.title);
    v("columns", t.columns);
    v("rows", t.rows);
}

/// One value a case gives a plot across its family, e.g. the mean weight at
/// its theta_o; with an interval (a confidence interval) when low <= high.
struct FamilyValue {
    std::string label;  ///< e.g. "mean weight (99% interval)": one curve per label and group
    double y = 0.0;
    double low = 0.0, high = -1.0;
};

template <class V, Model<FamilyValue> T>
void fields(V& v, T& f) {
    v("label", f.label);
    v("y", f.y);
    v("low", f.low);
    v("high", f.high);
}

/// One case's point on a plot across the cases of its family (a BSDF's
/// albedo against theta_o over its grid of outgoing directions). The report
/// gathers the points of every row with the same family and plot title into
/// one plot, a curve per value label and group (reports/family_plots.h). The
/// points live in the rows that make them, so a selection, a shard or a merge
/// of shards (which concatenates rows) plots exactly the cases it holds.
struct FamilyPoint {
    std::string family;  ///< the case's family, e.g. "rough_conductor"
    std::string title;   ///< the plot's, e.g. "albedo against theta_o"
    std::string x_label, y_label;
    bool log_y = false;
    /// The case's parameters other than x, e.g. "alpha=0.05": its curves'
    /// name within the family (empty when x is its only parameter).
    std::string group;
    double x = 0.0;
    std::vector<FamilyValue> values;
    /// Horizontal lines the values are judged against, e.g. {"energy bound", 1}.
    std::vector<Figure> limits{};
};

template <class V, Model<FamilyPoint> T>
void fields(V& v, T& p) {
    v("family", p.family);
    v("title", p.title);
    v("x_label", p.x_label);
    v("y_label", p.y_label);
    v("log_y", p.log_y);
    v("group", p.group);
    v("x", p.x);
    v("values", p.values);
    v.named_numbers("limits", p.limits);
}

/// Time spent in one part of a check's compute, e.g. "integration" or "sampling+binning".
struct PhaseTime {
    std::string phase;
    double seconds = 0.0;
};

template <class V, Model<PhaseTime> T>
void fields(V& v, T& p) {
    v.entry(p.phase, p.seconds);
}

/// One quantity a check judged, against its limit: a line of a row's
/// "Judged" table in the reports, written by the check's own rules
/// (validate/checks/judged.h) once the run's level is settled. NaN is never
/// within its limit.
struct JudgedQuantity {
    std::string quantity;  ///< e.g. "Pearson X² = 968.6 on 1023 dof: p-value"
    std::string value;     ///< e.g. "0.887"
    std::string limit;     ///< e.g. "≥ 5.83e-05 (0.8 × level)"; "counted" for a figure that is reported only
    enum class State {
        Within,    ///< within its limit
        Beyond,    ///< beyond it: the row fails
        Reported,  ///< reported beside the verdict, not judged
    };
    State state = State::Within;
    /// The value against its limit as one number, for the margin column
    /// (reports/terminal_table.h, row_margin), so that no report infers it
    /// from figure names: for a p-value, p over its limit (beyond below 1);
    /// for a size held under a limit, the size over that limit (beyond above
    /// 1). None for a count that must be 0 and for a reported figure.
    enum class Margin {
        None,
        POverLimit,  ///< p / limit
        OfLimit,     ///< size / limit
    };
    Margin margin_kind = Margin::None;
    double margin = 0.0;
};

template <>
struct EnumNames<JudgedQuantity::State> {
    static constexpr std::string_view noun = "judged state";
    static constexpr std::array<std::string_view, 3> names{"within", "beyond", "reported"};
};

template <>
struct EnumNames<JudgedQuantity::Margin> {
    static constexpr std::string_view noun = "judged margin";
    static constexpr std::array<std::string_view, 3> names{"none", "p_over_limit", "of_limit"};
};

template <class V, Model<JudgedQuantity> T>
void fields(V& v, T& j) {
    v("quantity", j.quantity);
    v("value", j.value);
    v("limit", j.limit);
    v("state", j.state);
    // Absent where there is none (and in files written before it was added).
    v.optional_group("margin", j.margin_kind != JudgedQuantity::Margin::None, [&](auto& g) {
        g("kind", j.margin_kind);
        g("value", j.margin);
    });
}

/// The outcome of one check on one warp case: one row of the pass/fail table.
struct CheckResult {
    std::string case_name;   ///< e.g. "uniform_cone[cos_theta_max=0.3]"
    std::string check_name;  ///< e.g. "roundtrip", "chi2"
    Verdict verdict = Verdict::Error;
    std::string summary;  ///< the key figure, short, for the table: "max |du| 3.0e-08"
    /// Why it failed or errored. On a pass, empty or a note worth reading that is
    /// not a failure (e.g. the bias an exhaustive sweep reports without failing it).
    std::string message;
    /// Set on a pass that could not have seen the effect its check states it
    /// can (a statistical test without the power to detect a 5% tilt of a
    /// marginal, for its cells or its samples): what it could not see.
    /// Reports show such a row as "weak", never as a plain pass; it is not a
    /// failure. Empty otherwise.
    std::string weak;

    std::vector<Figure> figures;  ///< every number worth keeping, by name
    /// Set by statistical checks. The runner turns it into the verdict with the
    /// multiple-test-corrected level (a NaN p-value fails).
    std::optional<double> p_value;
    std::optional<double> level;  ///< the per-test significance level applied, once known
    /// What the verdict was formed from: each judged quantity against its
    /// limit, by the check's rules (JudgedQuantity). Empty on errors and n/a rows.
    std::vector<JudgedQuantity> judged{};

    std::vector<Plot> plots;
    std::vector<Table> tables;
    /// This case's points on plots across its family (FamilyPoint).
    std::vector<FamilyPoint> family_points{};

    uint64_t stream_seed = 0;      ///< PCG32 seed of this (case, check) stream
    uint64_t stream_sequence = 0;  ///< PCG32 sequence index of this stream
    uint64_t samples = 0;          ///< inputs evaluated (0 where not meaningful)
    double seconds = 0.0;          ///< wall time of this check
    /// Where the compute time went, for the checks that time their parts
    /// (validate --timings); the rest of `seconds` is judging and evidence.
    std::vector<PhaseTime> phases;
    std::string rerun_command;     ///< the one command that reruns just this case and check
    /// Set by `validate` on the rows it writes: a digest of this row, all but
    /// its timings, and of its run's digest, which --merge checks
    /// (validate/run/run_digest.h). Empty where none was made.
    std::string digest;

    std::optional<double> figure(std::string_view name) const {
        for (const auto& f : figures)
            if (f.name == name) return f.value;
        return std::nullopt;
    }
};

template <class V, Model<CheckResult> T>
void fields(V& v, T& r) {
    v("case", r.case_name);
    v("check", r.check_name);
    v("verdict", r.verdict);
    v("summary", r.summary);
    v("message", r.message);
    v("weak", r.weak);
    v("p_value", r.p_value);
    v("level", r.level);
    v("judged", r.judged);
    v.named_numbers("figures", r.figures);
    v("samples", r.samples);
    v("seconds", r.seconds);
    v.named_numbers("phases", r.phases);
    v.group("stream", [&](auto& g) {
        g("seed", r.stream_seed);
        g("sequence", r.stream_sequence);
    });
    v("rerun_command", r.rerun_command);
    v("plots", r.plots);
    v("tables", r.tables);
    v("family_points", r.family_points);
    v("digest", r.digest);
}

/// The word a row's verdict is shown as: "weak" for a pass that could not
/// have seen its stated effect (CheckResult::weak), else the verdict's.
inline std::string_view verdict_word(const CheckResult& r) {
    return r.verdict == Verdict::Pass && !r.weak.empty() ? std::string_view("weak") : to_string(r.verdict);
}

/// How a check judges, for the legend of a report: written by the check
/// itself (Check::legend, validate/checks/check.h) and carried with the run,
/// so that a report explains every check it shows without knowing its name.
struct CheckLegend {
    std::string check;    ///< the check's name, as its rows give it
    std::string judged;   ///< what is judged, and what fails
    std::string p_value;  ///< how its p-value is formed ("" for a check without one)
};

template <class V, Model<CheckLegend> T>
void fields(V& v, T& l) {
    v("check", l.check);
    v("judged", l.judged);
    v("p_value", l.p_value);
}

/// What a whole run was: settings, environment and totals.
struct RunInfo {
    std::string tool_version;
    std::string command_line;
    uint64_t seed = 0;
    unsigned threads = 1;
    uint64_t samples = 0;           ///< default sample count per statistical check
    double family_alpha = 0.01;     ///< family-wise significance level asked for
    double per_test_alpha = 0.01;   ///< Šidák-corrected level applied to each statistical test
    int statistical_tests = 0;      ///< how many tests the correction covers
    bool strict = false;            ///< --strict: no float-resolution allowance was granted
    /// --max-float-bias: the factor past which an exhaustive sweep's float
    /// counts fail; 0: bias is only reported.
    double max_float_bias = 0.0;
    double wall_seconds = 0.0;
    std::string compiler;
    std::string machine;
    std::string started_at;  ///< ISO 8601, UTC
    /// Checks whose worker process was killed for going over its time budget
    /// (isolated runs; an in-process run asks such a check to stop and waits).
    int abandoned_checks = 0;
    /// Which part of a sharded run this is (validate --shard I/N): shard
    /// shard_index of shard_count, 1-based; 0 of 0 for a whole run.
    unsigned shard_index = 0;
    unsigned shard_count = 0;
    /// The (case, check) jobs of the whole run, all shards together.
    uint64_t run_jobs = 0;
    /// Set by `validate`: a digest of the settings that decide the figures and
    /// verdicts and of the whole run's job list, the same in every shard of one
    /// run, which --merge checks (validate/run/run_digest.h). Empty where none was made.
    std::string digest;
    /// The legend of each check that has a row, in the order the checks first
    /// appear (absent from files written before legends travelled with the
    /// run: read as none, and such a report shows no legend).
    std::vector<CheckLegend> legends;
};

/// The JSON document writes tool_version as its tool.version, the rest as its "run".
template <class V, Model<RunInfo> T>
void fields(V& v, T& i) {
    v("tool_version", i.tool_version);
    v("command_line", i.command_line);
    v("seed", i.seed);
    v("threads", i.threads);
    v("samples", i.samples);
    v("family_alpha", i.family_alpha);
    v("per_test_alpha", i.per_test_alpha);
    v("statistical_tests", i.statistical_tests);
    v("strict", i.strict);
    v("max_float_bias", i.max_float_bias);
    v("wall_seconds", i.wall_seconds);
    v("compiler", i.compiler);
    v("machine", i.machine);
    v("started_at", i.started_at);
    v("abandoned_checks", i.abandoned_checks);
    v("digest", i.digest);
    v.optional_group("shard", i.shard_count > 0, [&](auto& g) {
        g("index", i.shard_index);
        g("count", i.shard_count);
        g("jobs", i.run_jobs);
    });
    v.optional_group("legends", !i.legends.empty(), [&](auto& g) { g("checks", i.legends); });
}

/// How many rows of each verdict a run has: the "totals" of the JSON document.
struct Totals {
    uint64_t checks = 0;
    int passed = 0;
    int failed = 0;
    int errors = 0;
    int not_applicable = 0;
    bool operator==(const Totals&) const = default;
};

template <class V, Model<Totals> T>
void fields(V& v, T& t) {
    v("checks", t.checks);
    v("passed", t.passed);
    v("failed", t.failed);
    v("errors", t.errors);
    v("not_applicable", t.not_applicable);
}

struct RunResult {
    RunInfo info;
    std::vector<CheckResult> results;  ///< in registry order: case by case, check by check

    Totals totals() const {
        return {results.size(), count(Verdict::Pass), count(Verdict::Fail), count(Verdict::Error),
                count(Verdict::NotApplicable)};
    }

    int count(Verdict v) const {
        int n = 0;
        for (const auto& r : results) n += r.verdict == v;
        return n;
    }
    /// Whether every check that applies passed: n/a rows neither pass nor fail.
    bool all_passed() const { return count(Verdict::Fail) == 0 && count(Verdict::Error) == 0; }
};

}  // namespace warpcheck
