// warpcheck_fpr's body (validate/trust/fpr.h): measures how often the default suite
// fails on correct warps, for the built-in warps (warpcheck_fpr) or a
// program's own (e.g. tests/hard/hard_warps_fpr).
//
// Runs the selected default checks over many seeds and counts the runs with a
// failed check. With the Šidák correction, a run of correct warps should fail
// with probability close to the family-wise alpha (at most alpha when the tests
// are independent). The tool prints the measured fraction with its exact
// (Clopper-Pearson) confidence interval and says whether alpha lies inside it.
// A larger --alpha (e.g. 0.2) makes the comparison sharp with few runs.
// Seed-independent checks (exhaustive enumeration) run once, with the first seed.
//
// --power-check: the other side. The chi2 and unbinned checks state the
// smallest tilt of a marginal they detect with 90% probability; this simulates
// that tilt for every selected row whose marginal one input coordinate drives
// alone (validate/trust/power_simulation.h) over --runs seeds and says whether
// each detection rate lies within ten points of 0.9.
#include "validate/trust/fpr.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <iterator>
#include <map>
#include <optional>
#include <thread>
#include <utility>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>
#include <boost/math/distributions/binomial.hpp>
#include <fmt/format.h>

#include "chi2/binning.h"
#include "chi2/multiple_testing.h"
#include "validate/checks/shared/cell_power.h"
#include "validate/checks/shared/power_level.h"
#include "validate/trust/power_simulation.h"
#include "validate/api/registry.h"
#include "validate/run/runner.h"
#include "validate/run/thread_pool.h"
#include "validate/run/worker.h"

namespace {

using namespace warpcheck;

struct Interval {
    double lo = 0.0, hi = 1.0;
};

/// The exact (Clopper-Pearson) 95% interval of a binomial proportion.
Interval clopper_pearson(int trials, int successes) {
    using boost::math::binomial_distribution;
    return {binomial_distribution<>::find_lower_bound_on_p(trials, successes, 0.025),
            binomial_distribution<>::find_upper_bound_on_p(trials, successes, 0.025)};
}

int false_positive_rate(const std::vector<Job>& jobs, RunOptions options, int runs, uint64_t first_seed,
                        const Isolation& isolation) {
    // Checks that enumerate their inputs give the same result for every seed:
    // they run with the first seed only (a failure there fails every run).
    std::vector<Job> seeded_jobs;
    for (const Job& job : jobs)
        if (job.check->uses_seed()) seeded_jobs.push_back(job);

    int failed_runs = 0, tests = 0;
    bool unseeded_failed = false;  // a seed-independent check failed in the first run: every run counts it
    std::map<std::string, int> failures_by_check;
    for (int i = 0; i < runs; ++i) {
        options.seed = first_seed + static_cast<uint64_t>(i);
        const std::vector<Job>& run_list = i == 0 ? jobs : seeded_jobs;
        const RunResult run = run_jobs(run_list, options, {}, isolation);
        tests = run.info.statistical_tests;
        bool any = unseeded_failed;
        for (std::size_t k = 0; k < run.results.size(); ++k) {
            const CheckResult& r = run.results[k];
            if (r.verdict == Verdict::Pass || r.verdict == Verdict::NotApplicable) continue;
            any = true;
            unseeded_failed = unseeded_failed || !run_list[k].check->uses_seed();
            failures_by_check[r.check_name + " " + r.case_name]++;
            std::cerr << fmt::format("\nseed {}: {} {} {}: {}\n", options.seed, to_string(r.verdict), r.check_name,
                                     r.case_name, r.message);
        }
        failed_runs += any;
        std::cerr << fmt::format("\rseed {}: {} of {} runs failed so far", options.seed, failed_runs, i + 1);
    }
    std::cerr << "\n";

    const double rate = static_cast<double>(failed_runs) / runs;
    const Interval ci = clopper_pearson(runs, failed_runs);
    std::cout << fmt::format("{} runs of {} checks ({} statistical tests per run, {} samples, family-wise alpha {}, "
                             "{})\n",
                             runs, jobs.size(), tests, options.samples, options.alpha,
                             isolation.enabled ? "isolated" : "not isolated");
    std::cout << fmt::format("runs with a failure: {} = {:.4f}, 95% interval [{:.4f}, {:.4f}]\n", failed_runs, rate,
                             ci.lo, ci.hi);
    for (const auto& [what, n] : failures_by_check) std::cout << fmt::format("  {:4d}  {}\n", n, what);
    const bool agrees = options.alpha >= ci.lo && options.alpha <= ci.hi;
    std::cout << (agrees ? "agrees with" : "DISAGREES with") << " the family-wise level " << options.alpha << "\n";
    return agrees ? 0 : 1;
}

/// The statistical checks whose stated power --power-check simulates.
constexpr const char* kPowerChecks[] = {"chi2", "unbinned"};

/// The marginal a row states its power for (the weakest: the figure
/// power_tilt_eps_<m> that equals power_tilt_eps), and that figure's name.
std::optional<std::pair<int, std::string>> stated_marginal(const WarpCase& warp, const CheckResult& r) {
    const std::optional<double> stated = r.figure("power_tilt_eps");
    if (!stated || !std::isfinite(*stated)) return std::nullopt;
    const chi2::Binning binning(warp.domain());
    for (int axis = 0; axis < binning.parameter_dimension(); ++axis) {
        const std::string figure =
            "power_tilt_eps_" + figure_label(axis == 0 ? binning.u_label() : binning.v_label());
        if (r.figure(figure) == stated) return std::make_pair(axis, figure);
    }
    return std::nullopt;
}

/// --power-check: for every selected case and check of kPowerChecks whose
/// row states its power for a marginal that one input coordinate drives
/// alone and monotonically (driving_coordinate), the stated 90%-power tilt
/// simulated `runs` times: the detection rate should lie within ten points of
/// 0.9. Rows that cannot be simulated so are listed with the reason.
int power_check(const std::vector<Job>& jobs, RunOptions options, int runs,
                uint64_t first_seed) {
    options.seed = first_seed;
    std::cout << fmt::format("Detection of the stated 90%-power tilts: {} runs each, {} samples, family-wise alpha {} "
                             "(planned per-test level {:.3g}); within ten points of 0.9 agrees\n",
                             runs, options.samples, options.alpha,
                             chi2::sidak_level(options.alpha, kPlannedTestsPerRun));
    bool all_agree = true;
    int simulated = 0;
    ThreadPool pool(options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency()));
    for (const Job& job : jobs) {
        const WarpCase& warp = *job.warp;
        const Check& check = *job.check;
        if (std::find_if(std::begin(kPowerChecks), std::end(kPowerChecks),
                         [&](const char* c) { return check.name() == c; }) == std::end(kPowerChecks))
            continue;
        const CheckContext ctx(options, pool.executor(), job_stream(warp, check, options.seed));
        const CheckResult base = check.run(warp, ctx);
        const auto marginal = stated_marginal(warp, base);
        const std::optional<int> coordinate = marginal ? driving_coordinate(warp, marginal->first) : std::nullopt;
        const double stated = base.figure("power_tilt_eps").value_or(std::nan(""));
        if (!marginal || !coordinate || !(stated < 0.5)) {
            std::cout << fmt::format("  {:<9} {:<44} not simulated: {}\n", check.name(), warp.name(),
                                     !marginal ? "no stated marginal power"
                                     : !(stated < 0.5) ? fmt::format("stated tilt {:.3g} (weak)", stated)
                                                       : "no input coordinate drives " + marginal->second + " alone");
            continue;
        }
        const PowerSimulation s = simulate_stated_power(warp, check, *coordinate, marginal->second, options, runs);
        const Interval ci = clopper_pearson(s.runs, s.detected);
        const bool agrees = std::abs(s.rate() - 0.9) <= 0.1;
        all_agree = all_agree && agrees;
        ++simulated;
        std::cout << fmt::format("  {:<9} {:<44} u{} {:<26} eps {:.5f}: detected {:3d} of {} = {:.3f} [{:.3f}, {:.3f}] "
                                 "{}\n",
                                 s.check_name, s.case_name, *coordinate, s.figure, s.eps, s.detected, s.runs, s.rate(),
                                 ci.lo, ci.hi, agrees ? "agrees" : "DISAGREES");
    }
    std::cout << fmt::format("{} rows simulated; {}\n", simulated,
                             all_agree ? "every rate within ten points of 0.9" : "some rates DISAGREE");
    return all_agree ? 0 : 1;
}

}  // namespace

namespace warpcheck {

int fpr_main(int argc, char** argv, const FprProgram& program) {
    CLI::App app{program.description, program.name};
    RunOptions options;
    options.samples = RunOptions{}.samples;  // the default suite: the same samples as validate
    options.alpha = 0.2;
    int runs = 100;
    uint64_t first_seed = 1000;
    bool check_power = false;
    std::vector<std::string> filters, checks;
    app.add_option("--runs", runs, "Number of seeds")->check(CLI::Range(1, 1'000'000))->capture_default_str();
    app.add_option("--first-seed", first_seed, "Seeds used: first-seed .. first-seed + runs - 1")->capture_default_str();
    app.add_option("--samples", options.samples, "Samples per check")
        ->check(CLI::Range(uint64_t{1000}, uint64_t{100'000'000}))
        ->capture_default_str();
    auto* alpha = app.add_option("--alpha", options.alpha, "Family-wise level of each run (--power-check: 0.01)")
                      ->check(CLI::Range(1e-6, 0.5))
                      ->capture_default_str();
    app.add_option("--threads", options.threads, "Worker threads (0: all)")->capture_default_str();
    app.add_option("--filter", filters, "Only cases matching PATTERN (repeatable)");
    app.add_option("--check", checks, "Only this check (repeatable)");
    // Isolated by default, as validate runs: each job in a worker process under
    // its CPU time budget, so a busy machine or a crashing warp is one job's
    // ERROR (counted as a failed run), not a stalled or killed measurement.
    bool no_isolation = false;
    app.add_flag("--no-isolation", no_isolation, "Run the checks on threads of this process (for debuggers)");
    if (program.power_check)
        app.add_flag("--power-check", check_power,
                     "Instead: simulate each selected chi2 and unbinned row's stated 90%-power tilt and measure "
                     "its detection rate");
    CLI11_PARSE(app, argc, argv);

    Registry registry;
    try {
        register_builtin_checks(registry);  // first: a program may mark a flaw on one check of a case
        program.register_cases(registry);
    } catch (const std::exception& e) {  // registration may be foreign code: a clear error
        std::cerr << program.name << ": could not register the warps: " << e.what() << "\n";
        return 2;
    }
    const std::vector<Job> jobs = select_jobs(registry, filters, checks, options);
    if (check_power) {
        if (alpha->count() == 0) options.alpha = RunOptions{}.alpha;  // the level validate uses
        return power_check(jobs, options, runs, first_seed);
    }
    if (jobs.empty()) {
        std::cerr << program.name << ": no checks selected\n";
        return 2;
    }
    Isolation isolation;
    isolation.enabled = !no_isolation;
    return false_positive_rate(jobs, options, runs, first_seed, isolation);
}

}  // namespace warpcheck
