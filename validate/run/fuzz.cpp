#include "validate/run/fuzz.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include <fmt/format.h>

#include "chi2/multiple_testing.h"
#include "sampling/hash.h"
#include "sampling/pcg32.h"
#include "validate/run/runner.h"

namespace warpcheck {

std::vector<std::string> default_fuzz_checks() {
    return {"consistency",      "sample_pdf",    "weight",         "bsdf_weight",  "bsdf_delta", "bsdf_energy",
            "bsdf_expectation", "bsdf_spectral", "light_radiance", "light_support"};
}

namespace fuzz_detail {

/// A value as a case name writes it and a rerun reads it back: rounded to
/// float (a drawn double would name a case by 17 digits that its maker rounds
/// away), then to the decimal its name shows (parameter_value), so that the
/// point --fuzz-case makes from the name is the point that failed: a maker
/// that reads a parameter in double (theta_o for wo) sees the same value, and
/// one that reads it as a float the same float.
double as_float_value(double v) {
    if (!std::isfinite(v)) return v;
    return std::stod(parameter_value(static_cast<double>(static_cast<float>(v))));
}

/// The value of an end as a maker sees it: the end itself where it is closed,
/// else the nearest float inside the range.
double end_value(const ParamRange& r, bool low) {
    const double end = low ? r.lo : r.hi;
    const bool open = low ? r.lo_open : r.hi_open;
    double v = as_float_value(end);
    const float toward = static_cast<float>(low ? r.hi : r.lo);
    if (open || !r.contains(v)) v = as_float_value(std::nextafter(static_cast<float>(v), toward));
    if (!r.contains(v)) v = as_float_value(0.5 * (r.lo + r.hi));  // a range narrower than two floats
    return v;
}

/// The ends of each range of an axis, and a value a thousandth of the
/// range's width inside each (a near-end that is not yet the end), in order.
std::vector<double> axis_ends(const GridAxis& axis) {
    std::vector<double> ends;
    for (const ParamRange& r : axis.ranges) {
        ends.push_back(end_value(r, true));
        ends.push_back(end_value(r, false));
    }
    for (const ParamRange& r : axis.ranges) {
        const double w = r.hi - r.lo;
        for (const double v : {as_float_value(r.lo + 1e-3 * w), as_float_value(r.hi - 1e-3 * w)})
            if (r.contains(v)) ends.push_back(v);
    }
    return ends;
}

/// A value drawn from one of the axis's ranges: log-uniform where the range
/// is positive and spans two decades or more, else uniform.
double draw_in_range(const GridAxis& axis, Pcg32& rng) {
    const ParamRange& r = axis.ranges[rng.next_u32() % axis.ranges.size()];
    const double u = (static_cast<double>(rng.next_u32()) + 0.5) * 0x1p-32;
    const double v = r.lo > 0.0 && r.hi >= 100.0 * r.lo ? r.lo * std::pow(r.hi / r.lo, u) : r.lo + u * (r.hi - r.lo);
    const double f = as_float_value(v);
    return r.contains(f) ? f : end_value(r, u < 0.5);
}

bool in_declared_ranges(const CaseFamily& family, const std::vector<Parameter>& params) {
    for (std::size_t a = 0; a < family.axes.size(); ++a) {
        const GridAxis& axis = family.axes[a];
        if (axis.ranges.empty()) continue;
        bool inside = false;
        for (const ParamRange& r : axis.ranges) inside = inside || r.contains(params[a].value);
        if (!inside) return false;
    }
    return true;
}

/// How simple a value is, for shrinking: fewer significant decimal digits
/// first (0.1 before 0.123), then a smaller magnitude.
std::pair<int, double> simplicity(double v) {
    for (int digits = 1; digits <= 9; ++digits) {
        const double rounded = std::stod(fmt::format("{:.{}g}", v, digits));
        if (as_float_value(rounded) == as_float_value(v)) return {digits, std::abs(v)};
    }
    return {10, std::abs(v)};
}

/// The values a parameter may shrink to, simplest first: the grid's values
/// and the ranges' ends, then v rounded to fewer digits, then halfway toward
/// each end, each inside a declared range (an unranged axis keeps its grid).
std::vector<double> shrink_candidates(const GridAxis& axis, double v) {
    std::vector<double> c(axis.values.begin(), axis.values.end());
    for (const double e : axis_ends(axis)) c.push_back(e);
    for (int digits = 1; digits <= 6; ++digits) c.push_back(as_float_value(std::stod(fmt::format("{:.{}g}", v, digits))));
    for (const ParamRange& r : axis.ranges) c.push_back(as_float_value(0.5 * (v + (std::abs(v - r.lo) < std::abs(v - r.hi) ? r.lo : r.hi))));
    std::vector<double> out;
    for (const double x : c) {
        if (x == v || std::find(out.begin(), out.end(), x) != out.end()) continue;
        bool allowed = axis.ranges.empty() ? std::find(axis.values.begin(), axis.values.end(), x) != axis.values.end()
                                           : false;
        for (const ParamRange& r : axis.ranges) allowed = allowed || r.contains(x);
        if (allowed && simplicity(x) < simplicity(v)) out.push_back(x);
    }
    std::stable_sort(out.begin(), out.end(), [](double a, double b) { return simplicity(a) < simplicity(b); });
    return out;
}

/// The params of a family's point, in axis order.
std::vector<Parameter> point_params(const CaseFamily& family, const std::vector<double>& values) {
    std::vector<Parameter> p;
    for (std::size_t a = 0; a < family.axes.size(); ++a) p.push_back({family.axes[a].name, values[a]});
    return p;
}

}  // namespace fuzz_detail

std::vector<std::vector<Parameter>> fuzz_points(const CaseFamily& family, unsigned random_points, uint64_t seed) {
    const std::size_t n = family.axes.size();
    std::vector<double> base(n);
    std::vector<std::vector<double>> ends(n);
    for (std::size_t a = 0; a < n; ++a) {
        base[a] = family.axes[a].values.empty() ? 0.0 : family.axes[a].values.front();
        ends[a] = fuzz_detail::axis_ends(family.axes[a]);
    }
    std::vector<std::vector<double>> points;
    // Each axis's ends alone, the others at their first grid values (known good).
    for (std::size_t a = 0; a < n; ++a)
        for (const double e : ends[a]) {
            std::vector<double> p = base;
            p[a] = e;
            points.push_back(p);
        }
    // The corners: every ranged axis at the ends of its ranges at once (at most 64).
    std::vector<std::vector<double>> corners = {base};
    for (std::size_t a = 0; a < n; ++a) {
        if (family.axes[a].ranges.empty()) continue;
        std::vector<std::vector<double>> next;
        for (const auto& c : corners)
            for (std::size_t k = 0; k < 2 * family.axes[a].ranges.size(); ++k) {
                std::vector<double> p = c;
                p[a] = ends[a][k];
                next.push_back(p);
            }
        corners = std::move(next);
        if (corners.size() > 64) break;
    }
    Pcg32 rng(hash_string("fuzz/" + family.base.family), seed);
    if (corners.size() > 64) {
        std::vector<std::vector<double>> kept;
        for (std::size_t k = 0; k < 64; ++k) kept.push_back(corners[rng.next_u32() % corners.size()]);
        corners = std::move(kept);
    }
    points.insert(points.end(), corners.begin(), corners.end());
    // Random points: each ranged axis an end one time in three, else drawn in a range.
    for (unsigned k = 0; k < random_points; ++k) {
        std::vector<double> p(n);
        for (std::size_t a = 0; a < n; ++a) {
            const GridAxis& axis = family.axes[a];
            if (axis.ranges.empty()) p[a] = axis.values[rng.next_u32() % axis.values.size()];
            else if (rng.next_u32() % 3 == 0) p[a] = ends[a][rng.next_u32() % ends[a].size()];
            else p[a] = fuzz_detail::draw_in_range(axis, rng);
        }
        points.push_back(p);
    }
    std::vector<std::vector<Parameter>> out;
    std::set<std::vector<double>> seen;
    for (const auto& p : points)
        if (seen.insert(p).second) out.push_back(fuzz_detail::point_params(family, p));
    return out;
}

std::unique_ptr<WarpCase> make_family_case(const CaseFamily& family, const std::vector<Parameter>& params,
                                           std::string& refusal) {
    WarpCaseInfo info = family.base;
    info.params.insert(info.params.end(), params.begin(), params.end());
    const std::string expected = case_name(info.family, info.params);
    try {
        std::unique_ptr<WarpCase> warp = family.make(std::move(info), GridPoint(params));
        if (!warp) {
            refusal = "the maker returned no case";
            return nullptr;
        }
        if (warp->name() != expected) {
            refusal = "the maker named its case " + warp->name();
            return nullptr;
        }
        validate_case(*warp);
        return warp;
    } catch (const std::exception& e) {
        refusal = e.what();
    } catch (...) {
        refusal = "the maker threw an exception that is not a std::exception";
    }
    return nullptr;
}

std::unique_ptr<WarpCase> make_case_from_name(const Registry& registry, const std::string& name, std::string& problem) {
    const auto open = name.find('[');
    if (open == std::string::npos || name.back() != ']') {
        problem = "'" + name + "' is not family[name=value,...]";
        return nullptr;
    }
    const CaseFamily* family = registry.find_family(name.substr(0, open));
    if (!family) {
        problem = "no family '" + name.substr(0, open) + "' (families are registered over grids)";
        return nullptr;
    }
    std::map<std::string, double> given;
    std::stringstream list(name.substr(open + 1, name.size() - open - 2));
    for (std::string item; std::getline(list, item, ',');) {
        const auto eq = item.find('=');
        std::size_t used = 0;
        double v = 0.0;
        try {
            v = eq == std::string::npos ? 0.0 : std::stod(item.substr(eq + 1), &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (eq == std::string::npos || used != item.size() - eq - 1 || !std::isfinite(v)) {
            problem = "'" + item + "' is not name=number";
            return nullptr;
        }
        given[item.substr(0, eq)] = v;
    }
    std::vector<Parameter> params;
    for (const Parameter& p : family->base.params) given.erase(p.name);  // the family's fixed ones may be named
    for (const GridAxis& axis : family->axes) {
        const auto it = given.find(axis.name);
        if (it == given.end()) {
            problem = "no value for " + axis.name + " of " + family->base.family;
            return nullptr;
        }
        params.push_back({axis.name, it->second});
        given.erase(it);
    }
    if (!given.empty()) {
        problem = family->base.family + " has no parameter " + given.begin()->first;
        return nullptr;
    }
    std::string refusal;
    std::unique_ptr<WarpCase> warp = make_family_case(*family, params, refusal);
    if (!warp) problem = family->base.family + " refuses these parameters: " + refusal;
    return warp;
}

namespace fuzz_detail {

/// The jobs of the named checks on one case (those that apply; n/a is no finding).
std::vector<Job> jobs_for(const Registry& registry, const WarpCase& warp, const std::vector<std::string>& checks) {
    std::vector<Job> jobs;
    for (const auto& check : registry.checks()) {
        if (std::find(checks.begin(), checks.end(), check->name()) == checks.end()) continue;
        if (!check_is_for(*check, warp) || !check->applicability(warp).applies()) continue;
        jobs.push_back({&warp, check.get()});
    }
    return jobs;
}

struct Point {
    const CaseFamily* family = nullptr;
    std::vector<Parameter> params;
    std::unique_ptr<WarpCase> warp;
};

/// Whether `params` of the family still fail `check` (at the fuzz run's level); the row where it does.
std::optional<CheckResult> still_fails(const CaseFamily& family,
                                       const std::vector<Parameter>& params, const Check& check,
                                       const FuzzOptions& options, int family_tests) {
    std::string refusal;
    const std::unique_ptr<WarpCase> warp = make_family_case(family, params, refusal);
    if (!warp || !check_is_for(check, *warp) || !check.applicability(*warp).applies()) return std::nullopt;
    RunOptions run = options.run;
    run.family_tests = family_tests;
    RunResult r = run_jobs({{warp.get(), &check}}, run, {}, options.isolation);
    if (r.results.size() == 1 && (r.results[0].verdict == Verdict::Fail || r.results[0].verdict == Verdict::Error))
        return r.results[0];
    return std::nullopt;
}

/// Greedy shrinking: each parameter in turn to its simplest value that still
/// fails, until a whole pass changes nothing or the reruns run out; returns
/// the reruns used, `best` and `best_row` left at the simplest failing point.
unsigned shrink(const CaseFamily& family, const Check& check, const FuzzOptions& options, int family_tests,
                std::vector<Parameter>& best, CheckResult& best_row) {
    unsigned runs = 0;
    for (bool changed = true; changed && runs < options.max_shrink_runs;) {
        changed = false;
        for (std::size_t a = 0; a < best.size() && !changed; ++a)
            for (const double v : shrink_candidates(family.axes[a], best[a].value)) {
                if (runs >= options.max_shrink_runs) break;
                std::vector<Parameter> trial = best;
                trial[a].value = v;
                ++runs;
                if (auto row = still_fails(family, trial, check, options, family_tests)) {
                    best = std::move(trial);
                    best_row = std::move(*row);
                    changed = true;
                    break;
                }
            }
    }
    return runs;
}

}  // namespace fuzz_detail

FuzzReport run_fuzz(const Registry& registry, const FuzzOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<std::string> checks = options.checks.empty() ? default_fuzz_checks() : options.checks;
    FuzzReport report;
    std::vector<fuzz_detail::Point> points;
    for (const CaseFamily& family : registry.families()) {
        if (!family.fuzzable()) continue;
        bool wanted = options.families.empty();
        for (const std::string& pattern : options.families)  // a family's full name selects only it
            wanted = wanted || (registry.find_family(pattern) ? family.base.family == pattern
                                                              : name_matches(family.base.family, pattern));
        if (!wanted) continue;
        ++report.families;
        for (std::vector<Parameter>& params : fuzz_points(family, options.random_points, options.run.seed)) {
            std::string refusal;
            std::unique_ptr<WarpCase> warp = make_family_case(family, params, refusal);
            if (!warp) {
                WarpCaseInfo info = family.base;
                info.params.insert(info.params.end(), params.begin(), params.end());
                if (fuzz_detail::in_declared_ranges(family, params))
                    report.refusals.push_back(case_name(info.family, info.params) + ": " + refusal);
                continue;
            }
            points.push_back({&family, std::move(params), std::move(warp)});
        }
    }
    report.points = points.size();
    std::vector<Job> jobs;
    std::vector<std::size_t> owner;
    for (std::size_t i = 0; i < points.size(); ++i)
        for (const Job& job : fuzz_detail::jobs_for(registry, *points[i].warp, checks)) {
            jobs.push_back(job);
            owner.push_back(i);
        }
    report.jobs = jobs.size();
    report.statistical_tests = std::max(1, statistical_tests(jobs));
    report.per_test_level = chi2::sidak_level(options.run.alpha, report.statistical_tests);
    RunOptions run = options.run;
    run.family_tests = report.statistical_tests;
    report.run = run_jobs(jobs, run, {}, options.isolation);
    const RunResult& result = report.run;

    // Group the failures by (family, check); shrink the first of each group.
    std::map<std::pair<std::string, std::string>, std::vector<std::size_t>> failures;
    std::vector<std::pair<std::string, std::string>> order;
    for (std::size_t j = 0; j < result.results.size(); ++j) {
        const CheckResult& r = result.results[j];
        if (r.verdict != Verdict::Fail && r.verdict != Verdict::Error) continue;
        const auto key = std::make_pair(points[owner[j]].family->base.family, r.check_name);
        if (failures[key].empty()) order.push_back(key);
        failures[key].push_back(j);
    }
    for (const auto& key : order) {
        const std::size_t first = failures[key].front();
        const fuzz_detail::Point& found = points[owner[first]];
        const Check& check = *jobs[first].check;
        std::vector<Parameter> best = found.params;
        CheckResult best_row = result.results[first];
        report.shrink_runs += fuzz_detail::shrink(*found.family, check, options, report.statistical_tests, best, best_row);
        WarpCaseInfo info = found.family->base;
        info.params.insert(info.params.end(), best.begin(), best.end());
        FuzzFinding f;
        f.family = key.first;
        f.check = key.second;
        f.found_case = found.warp->name();
        f.shrunk_case = case_name(info.family, info.params);
        f.verdict = best_row.verdict;
        f.summary = best_row.summary;
        f.message = best_row.message;
        f.failing_points = failures[key].size();
        f.rerun = rerun_command(options.run.program, f.shrunk_case, f.check, options.run.seed, options.run.samples,
                                options.run.max_float_bias);
        f.rerun = fuzz_case_rerun(f.rerun);
        report.findings.push_back(std::move(f));
    }
    for (CheckResult& r : report.run.results) r.rerun_command = fuzz_case_rerun(r.rerun_command);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
}

std::string fuzz_case_rerun(std::string rerun) {
    const auto filter = rerun.find("--filter");
    if (filter != std::string::npos) rerun.replace(filter, 8, "--fuzz-case");
    return rerun;
}

std::string fuzz_report_text(const FuzzReport& report) {
    std::string out;
    for (const FuzzFinding& f : report.findings) {
        out += fmt::format("{} {} on {} of the points of {}\n", f.verdict == Verdict::Error ? "ERROR" : "FAIL", f.check,
                           f.failing_points, f.family);
        out += fmt::format("  found at   {}\n", f.found_case);
        out += fmt::format("  shrunk to  {}\n", f.shrunk_case);
        out += fmt::format("  {}\n", f.summary);
        if (!f.message.empty()) out += fmt::format("  {}\n", f.message);
        out += fmt::format("  rerun: {}\n", f.rerun);
    }
    for (const std::string& r : report.refusals) out += "REFUSED inside a declared range: " + r + "\n";
    out += fmt::format(
        "fuzz: {} families, {} points, {} jobs ({} statistical, per-test level {:.3g}), {} shrink runs: {} findings, "
        "{} refusals in {:.1f} s\n",
        report.families, report.points, report.jobs, report.statistical_tests, report.per_test_level, report.shrink_runs,
        report.findings.size(), report.refusals.size(), report.seconds);
    return out;
}

}  // namespace warpcheck
