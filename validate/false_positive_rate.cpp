// warpcheck_fpr: measures how often the default suite fails on correct warps.
//
// Runs the selected default checks over many seeds and counts the runs with a
// failed check. With the Šidák correction, a run of correct warps should fail
// with probability close to the family-wise alpha (at most alpha when the tests
// are independent). The tool prints the measured fraction with its exact
// (Clopper-Pearson) confidence interval and says whether alpha lies inside it.
// A larger --alpha (e.g. 0.2) makes the comparison sharp with few runs.
// Seed-independent checks (exhaustive enumeration) run once, with the first seed.
#include <iostream>
#include <map>

#include <CLI/CLI.hpp>
#include <boost/math/distributions/binomial.hpp>
#include <fmt/format.h>

#include "validate/registry.h"
#include "validate/runner.h"

int main(int argc, char** argv) {
    using namespace warpcheck;
    CLI::App app{"Measures the false-positive rate of warpcheck's default suite over many seeds", "warpcheck_fpr"};
    RunOptions options;
    options.samples = RunOptions{}.samples;  // the default suite: the same samples as validate
    options.alpha = 0.2;
    int runs = 100;
    uint64_t first_seed = 1000;
    std::vector<std::string> filters, checks;
    app.add_option("--runs", runs, "Number of seeds")->check(CLI::Range(1, 1'000'000))->capture_default_str();
    app.add_option("--first-seed", first_seed, "Seeds used: first-seed .. first-seed + runs - 1")->capture_default_str();
    app.add_option("--samples", options.samples, "Samples per check")
        ->check(CLI::Range(uint64_t{1000}, uint64_t{100'000'000}))
        ->capture_default_str();
    app.add_option("--alpha", options.alpha, "Family-wise level of each run")->check(CLI::Range(1e-6, 0.5))
        ->capture_default_str();
    app.add_option("--threads", options.threads, "Worker threads (0: all)")->capture_default_str();
    app.add_option("--filter", filters, "Only cases matching PATTERN (repeatable)");
    app.add_option("--check", checks, "Only this check (repeatable)");
    CLI11_PARSE(app, argc, argv);

    Registry registry;
    register_builtin_cases(registry);
    register_builtin_checks(registry);
    const std::vector<Job> jobs = select_jobs(registry, filters, checks, options);
    if (jobs.empty()) {
        std::cerr << "warpcheck_fpr: no checks selected\n";
        return 2;
    }

    // Checks that enumerate their inputs give the same result for every seed:
    // they run with the first seed only (a failure there fails every run).
    std::vector<Job> seeded_jobs;
    for (const Job& job : jobs)
        if (job.check->uses_seed()) seeded_jobs.push_back(job);

    int failed_runs = 0, tests = 0;
    std::map<std::string, int> failures_by_check;
    for (int i = 0; i < runs; ++i) {
        options.seed = first_seed + static_cast<uint64_t>(i);
        const RunResult run = run_jobs(i == 0 ? jobs : seeded_jobs, options);
        tests = run.info.statistical_tests;
        bool any = false;
        for (const auto& r : run.results) {
            if (r.verdict == Verdict::Pass || r.verdict == Verdict::NotApplicable) continue;
            any = true;
            failures_by_check[r.check_name + " " + r.case_name]++;
            std::cerr << fmt::format("\nseed {}: {} {} {}: {}\n", options.seed, to_string(r.verdict), r.check_name,
                                     r.case_name, r.message);
        }
        failed_runs += any;
        std::cerr << fmt::format("\rseed {}: {} of {} runs failed so far", options.seed, failed_runs, i + 1);
    }
    std::cerr << "\n";

    using boost::math::binomial_distribution;
    const double rate = static_cast<double>(failed_runs) / runs;
    const double lo = binomial_distribution<>::find_lower_bound_on_p(runs, failed_runs, 0.025);
    const double hi = binomial_distribution<>::find_upper_bound_on_p(runs, failed_runs, 0.025);
    std::cout << fmt::format("{} runs of {} checks ({} statistical tests per run, {} samples, family-wise alpha {})\n",
                             runs, jobs.size(), tests, options.samples, options.alpha);
    std::cout << fmt::format("runs with a failure: {} = {:.4f}, 95% interval [{:.4f}, {:.4f}]\n", failed_runs, rate,
                             lo, hi);
    for (const auto& [what, n] : failures_by_check) std::cout << fmt::format("  {:4d}  {}\n", n, what);
    const bool agrees = options.alpha >= lo && options.alpha <= hi;
    std::cout << (agrees ? "agrees with" : "DISAGREES with") << " the family-wise level " << options.alpha << "\n";
    return agrees ? 0 : 1;
}
