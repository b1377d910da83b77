// The result model: plain data that every check produces and every output format
// (terminal table, JSON, JUnit XML, HTML) is a view of. No behaviour lives here.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace warpcheck {

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

/// A named number, e.g. {"p_value", 0.43} or {"max_error", 1.2e-7}.
struct Figure {
    std::string name;
    double value = 0.0;
};

/// One curve or bar series of a plot.
struct Series {
    std::string label;
    std::vector<double> x;
    std::vector<double> y;
};

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
};

/// A small table of evidence, e.g. the worst inputs of a round trip.
struct Table {
    std::string title;
    std::vector<std::string> columns;
    std::vector<std::vector<std::string>> rows;
};

/// Time spent in one part of a check's compute, e.g. "integration" or "sampling+binning".
struct PhaseTime {
    std::string phase;
    double seconds = 0.0;
};

/// The outcome of one check on one warp case: one row of the pass/fail table.
struct CheckResult {
    std::string case_name;   ///< e.g. "uniform_cone[cos_theta_max=0.3]"
    std::string check_name;  ///< e.g. "roundtrip", "chi2"
    Verdict verdict = Verdict::Error;
    std::string summary;  ///< the key figure, short, for the table: "max |du| 3.0e-08"
    /// Why it failed or errored. On a pass, empty or a note worth reading that is
    /// not a failure (e.g. the bias an exhaustive sweep reports without failing it).
    std::string message;

    std::vector<Figure> figures;  ///< every number worth keeping, by name
    /// Set by statistical checks. The runner turns it into the verdict with the
    /// multiple-test-corrected level (a NaN p-value fails).
    std::optional<double> p_value;
    std::optional<double> level;  ///< the per-test significance level applied, once known

    std::vector<Plot> plots;
    std::vector<Table> tables;

    uint64_t stream_seed = 0;      ///< PCG32 seed of this (case, check) stream
    uint64_t stream_sequence = 0;  ///< PCG32 sequence index of this stream
    uint64_t samples = 0;          ///< inputs evaluated (0 where not meaningful)
    double seconds = 0.0;          ///< wall time of this check
    /// Where the compute time went, for the checks that time their parts
    /// (validate --timings); the rest of `seconds` is judging and evidence.
    std::vector<PhaseTime> phases;
    std::string rerun_command;     ///< the one command that reruns just this case and check

    std::optional<double> figure(std::string_view name) const {
        for (const auto& f : figures)
            if (f.name == name) return f.value;
        return std::nullopt;
    }
};

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
};

struct RunResult {
    RunInfo info;
    std::vector<CheckResult> results;  ///< in registry order: case by case, check by check

    int count(Verdict v) const {
        int n = 0;
        for (const auto& r : results) n += r.verdict == v;
        return n;
    }
    /// Whether every check that applies passed: n/a rows neither pass nor fail.
    bool all_passed() const { return count(Verdict::Fail) == 0 && count(Verdict::Error) == 0; }
};

}  // namespace warpcheck
