#include "validate/runner.h"

#include <sys/utsname.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <exception>

#include <fmt/format.h>

namespace warpcheck {

StreamId job_stream(const WarpCase& warp, const Check& check, uint64_t seed) {
    return stream_for(warp.name() + "/" + check.name(), seed);
}

std::vector<Job> select_jobs(const Registry& registry, const std::vector<std::string>& case_patterns,
                             const std::vector<std::string>& check_names, const RunOptions& options) {
    std::vector<Job> jobs;
    for (const auto& warp : registry.cases()) {
        bool selected = case_patterns.empty();
        for (const auto& pattern : case_patterns) {
            // A pattern that is a case's full name selects only that case.
            selected = selected || (registry.find_case(pattern) ? warp->name() == pattern
                                                                : name_matches(warp->name(), pattern));
        }
        if (!selected) continue;
        for (const auto& check : registry.checks()) {
            const bool wanted = check_names.empty() ? check->runs_by_default(options)
                                                    : std::find(check_names.begin(), check_names.end(),
                                                                check->name()) != check_names.end();
            if (wanted && check->applies_to(*warp)) jobs.push_back({warp.get(), check.get()});
        }
    }
    return jobs;
}

double sidak_level(double alpha, int tests) {
    if (tests <= 1) return alpha;
    // 1 - (1 - alpha)^(1/m), written with log1p/expm1 so tiny levels keep their digits.
    return -std::expm1(std::log1p(-alpha) / tests);
}

void apply_multiple_test_correction(RunResult& run, double family_alpha) {
    int tests = 0;
    for (const auto& r : run.results) tests += r.p_value.has_value();
    const double level = sidak_level(family_alpha, tests);
    run.info.family_alpha = family_alpha;
    run.info.statistical_tests = tests;
    run.info.per_test_alpha = level;
    for (auto& r : run.results) {
        if (!r.p_value) continue;
        r.level = level;
        r.figures.push_back({"level", level});
        if (r.verdict == Verdict::Pass && !(*r.p_value >= level)) {
            r.verdict = Verdict::Fail;
            r.message = std::isnan(*r.p_value)
                            ? "p-value is NaN"
                            : fmt::format("p-value {:.3g} is below the corrected level {:.3g} (family-wise {} over {} "
                                          "tests, Sidak)",
                                          *r.p_value, level, family_alpha, tests);
        }
    }
}

namespace {

std::string machine_description() {
    utsname u{};
    std::string text = uname(&u) == 0 ? fmt::format("{} {} {}", u.sysname, u.release, u.machine) : "unknown";
    return text + fmt::format(", {} hardware threads", std::thread::hardware_concurrency());
}

std::string utc_now() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

}  // namespace

RunResult run_jobs(const std::vector<Job>& jobs, const RunOptions& options, const ProgressCallback& progress) {
    const auto start = std::chrono::steady_clock::now();
    const unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    ThreadPool pool(threads);

    RunResult run;
    run.info.seed = options.seed;
    run.info.threads = threads;
    run.info.samples = options.samples;
    run.info.compiler = fmt::format("g++ {}", __VERSION__);
    run.info.machine = machine_description();
    run.info.started_at = utc_now();
    run.results.resize(jobs.size());

    std::atomic<std::size_t> done{0};
    std::mutex progress_mutex;
    pool.parallel_for(jobs.size(), [&](std::size_t i) {
        const Job& job = jobs[i];
        const StreamId stream = job_stream(*job.warp, *job.check, options.seed);
        CheckContext ctx(options, pool, stream);
        const auto t0 = std::chrono::steady_clock::now();
        CheckResult r;
        try {
            r = job.check->run(*job.warp, ctx);
        } catch (const std::exception& e) {
            r = CheckResult{};
            r.verdict = Verdict::Error;
            r.message = fmt::format("the check could not run: {}", e.what());
            r.summary = "error: exception";
        } catch (...) {
            r = CheckResult{};
            r.verdict = Verdict::Error;
            r.message = "the check could not run: unknown exception";
            r.summary = "error: exception";
        }
        r.case_name = job.warp->name();
        r.check_name = job.check->name();
        r.stream_seed = stream.seed;
        r.stream_sequence = stream.sequence;
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        r.rerun_command = fmt::format("validate --filter {} --check {} --seed {} --samples {}",
                                      shell_quote(r.case_name), r.check_name, options.seed, options.samples);
        run.results[i] = std::move(r);
        const std::size_t n = ++done;
        if (progress) {
            std::lock_guard lock(progress_mutex);
            progress(n, jobs.size(), job.check->name() + " " + job.warp->name());
        }
    });

    apply_multiple_test_correction(run, options.alpha);
    run.info.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return run;
}

}  // namespace warpcheck
