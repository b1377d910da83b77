#include "validate/run/runner.h"

#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <atomic>
#include <condition_variable>
#include <cstdlib>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "chi2/multiple_testing.h"
#include "reports/terminal_table.h"
#include "reports/text.h"
#include "validate/checks/checks.h"
#include "validate/run/thread_pool.h"
#include "warpcheck/version.h"

namespace warpcheck {

StreamId job_stream(const WarpCase& warp, const Check& check, uint64_t seed) {
    return stream_for(warp.name() + "/" + check.name(), seed);
}

bool check_is_for(const Check& check, const WarpCase& warp) {
    return (warp.sample_returns() == SampleReturns::Bsdf) == check.about_bsdfs();
}

std::vector<Job> select_jobs(const Registry& registry, const std::vector<std::string>& case_patterns,
                             const std::vector<std::string>& check_names, const RunOptions& options) {
    std::vector<Job> jobs;
    for (const auto& warp : registry.cases()) {
        bool selected = case_patterns.empty(), named = false;
        for (const auto& pattern : case_patterns) {
            // A pattern that is a case's full name selects only that case.
            named = named || warp->name() == pattern;
            selected = selected || (registry.find_case(pattern) ? warp->name() == pattern
                                                                : name_matches(warp->name(), pattern));
        }
        if (!selected) continue;
        const bool run_flawed = options.include_flawed || named;
        if (!registry.known_flaw(*warp).empty() && !run_flawed) continue;
        for (const auto& check : registry.checks()) {
            const bool wanted = check_names.empty() ? check->runs_by_default(options)
                                                    : std::find(check_names.begin(), check_names.end(),
                                                                check->name()) != check_names.end();
            if (!wanted || (!registry.known_flaw(*warp, check->name()).empty() && !run_flawed)) continue;
            if (!check_is_for(*check, *warp)) continue;
            const Applicability applicability = check->applicability(*warp);
            if (applicability.applies()) jobs.push_back({warp.get(), check.get()});
            else if (!applicability.not_applicable_because().empty())
                jobs.push_back({warp.get(), check.get(), applicability.not_applicable_because()});
        }
    }
    return jobs;
}

std::optional<Shard> parse_shard(std::string_view spec) {
    const auto slash = spec.find('/');
    const auto number = [](std::string_view text) -> std::optional<unsigned> {
        if (text.empty() || text.size() > 7 || text.find_first_not_of("0123456789") != std::string_view::npos)
            return std::nullopt;
        unsigned v = 0;
        for (char c : text) v = v * 10 + static_cast<unsigned>(c - '0');
        return v;
    };
    if (slash == std::string_view::npos) return std::nullopt;
    const auto index = number(spec.substr(0, slash)), count = number(spec.substr(slash + 1));
    if (!index || !count || *index < 1 || *index > *count || *count > 1'000'000) return std::nullopt;
    return Shard{*index, *count};
}

std::vector<Job> shard_jobs(const std::vector<Job>& jobs, Shard shard) {
    std::vector<Job> part;
    for (std::size_t i = shard.index - 1; i < jobs.size(); i += shard.count) part.push_back(jobs[i]);
    return part;
}

int statistical_tests(const std::vector<Job>& jobs) {
    return static_cast<int>(std::count_if(jobs.begin(), jobs.end(), [](const Job& j) { return j.check->statistical(); }));
}

void apply_multiple_test_correction(RunResult& run, double family_alpha, std::optional<int> family_tests) {
    int tests = 0;
    for (const auto& r : run.results) tests += r.p_value.has_value();
    if (family_tests) tests = *family_tests;
    const double level = chi2::sidak_level(family_alpha, tests);
    run.info.family_alpha = family_alpha;
    run.info.statistical_tests = tests;
    run.info.per_test_alpha = level;
    for (auto& r : run.results) {
        if (!r.p_value) continue;
        r.level = level;
        r.figures.push_back({"level", level});
        if (r.verdict == Verdict::Pass && !(*r.p_value >= level)) {
            r.verdict = Verdict::Fail;
            r.weak.clear();  // it saw a deviation: what it could not have seen no longer matters
            r.message = std::isnan(*r.p_value)
                            ? "p-value is NaN"
                            : fmt::format("p-value {:.3g} is below the corrected level {:.3g} (family-wise {} over {} "
                                          "tests, Sidak)",
                                          *r.p_value, level, family_alpha, tests);
        }
    }
}

std::string machine_description() {
    utsname u{};
    std::string text = uname(&u) == 0 ? fmt::format("{} {} {}", u.sysname, u.release, u.machine) : "unknown";
    return text + fmt::format(", {} hardware threads, chi-square lanes: {}", std::thread::hardware_concurrency(),
                              chi2_vector_path());
}

namespace {

std::string utc_now() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

std::string shell_quote(const std::string& s) {
    // A name a terminal would not show as it is (control bytes, invalid UTF-8)
    // goes in bash's $'...' with every such byte as \xNN: the command then
    // shows no raw control byte and still reruns the case.
    if (terminal_text(s) != s) {
        std::string q = "$'";
        for (const char c : s) {
            const auto byte = static_cast<unsigned char>(c);
            if (byte < 0x20 || byte >= 0x7F) q += fmt::format("\\x{:02x}", byte);
            else q += c == '\\' || c == '\'' ? std::string{'\\', c} : std::string(1, c);
        }
        return q + "'";
    }
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// A program's path as typed when the shell takes it as it is, else quoted.
std::string shell_word(const std::string& s) {
    const bool plain = !s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                         "0123456789_-+./:=@%,") == std::string::npos;
    return plain ? s : shell_quote(s);
}

}  // namespace

namespace {

using Clock = std::chrono::steady_clock;

// An in-process run whose warp calls exit() or quick_exit() would end with the
// warp's status (0 for exit(0)) and no report. While a run is on, a handler
// says on standard error which check's warp it was and ends the process with
// status 1 (kExitFail of validate/cli/cli.h: a check could not run).
struct ActiveRun {
    const std::vector<Job>* jobs = nullptr;
    const std::vector<std::atomic<bool>>* running = nullptr;
};
std::atomic<const ActiveRun*> g_active_run{nullptr};

std::string exit_culprit(const ActiveRun& run) {
    const void* tag = ThreadPool::current_tag();  // the job this thread works for (thread_pool.h)
    const std::vector<Job>& jobs = *run.jobs;
    const std::less<const void*> before;
    if (tag && !before(tag, jobs.data()) && before(tag, jobs.data() + jobs.size())) {
        const Job& job = *static_cast<const Job*>(tag);
        return fmt::format("the warp of case {} called exit() during check {}", terminal_text(job.warp->name()),
                           job.check->name());
    }
    std::string running;
    for (std::size_t i = 0; i < jobs.size(); ++i)
        if ((*run.running)[i])
            running += fmt::format("\n  {} {}", jobs[i].check->name(), terminal_text(jobs[i].warp->name()));
    return "exit() was called from a thread that runs no check; the checks running were:" + running;
}

// glibc pops each exit handler once, whichever thread calls exit(): when two
// threads call it together (a warp's loop on two pool threads), the second
// finds the handler gone and ends the process with the warp's status while the
// first still writes the report. So the handler is registered kExitHandlerCopies
// times; the first thread in reports, and every later one (up to that many at
// once, more than a run has threads) waits in its copy for the report's _exit(1).
constexpr int kExitHandlerCopies = 64;
std::atomic<bool> g_exit_reported{false};

extern "C" void report_exit_during_run() {
    const ActiveRun* run = g_active_run.load();
    if (!run) return;
    if (g_exit_reported.exchange(true))
        for (;;) ::pause();  // another thread writes the report and ends the process
    const std::string text = fmt::format("validate: {}\nThe in-process run (--no-isolation) is abandoned and no "
                                         "report is written; without --no-isolation that check is one ERROR row.\n",
                                         exit_culprit(*run));
    (void)!::write(STDERR_FILENO, text.data(), text.size());
    ::_exit(1);
}

/// Reports an exit() during the run it spans (see above).
class ExitDuringRunGuard {
public:
    ExitDuringRunGuard(const std::vector<Job>& jobs, const std::vector<std::atomic<bool>>& running)
        : run_{&jobs, &running} {
        static std::once_flag registered;
        std::call_once(registered, [] {
            for (int i = 0; i < kExitHandlerCopies; ++i) {
                std::atexit(report_exit_during_run);
                std::at_quick_exit(report_exit_during_run);
            }
        });
        g_active_run = &run_;
    }
    ~ExitDuringRunGuard() { g_active_run = nullptr; }
    ExitDuringRunGuard(const ExitDuringRunGuard&) = delete;
    ExitDuringRunGuard& operator=(const ExitDuringRunGuard&) = delete;

private:
    ActiveRun run_;
};

// Jobs on `threads` job threads of this process, which share one pool for the
// work within a job, while the calling thread watches the clock. A check over
// its budget can only be asked to stop (CheckContext::throw_if_cancelled) and
// is waited for: a warp that never returns hangs an in-process run.
std::vector<CheckResult> run_jobs_in_process(const std::vector<Job>& jobs, const RunOptions& options,
                                             unsigned threads, const ProgressCallback& progress) {
    const std::size_t n = jobs.size();
    std::vector<CheckResult> results(n);
    std::vector<std::atomic<bool>> cancel(n), active(n);
    std::vector<std::optional<Clock::time_point>> running(n);
    const ExitDuringRunGuard exit_guard(jobs, active);
    std::mutex mutex;
    std::condition_variable changed;
    std::size_t next = 0, done = 0;
    ThreadPool pool(threads);  // outlives the job threads below
    auto job_thread = [&] {
        for (;;) {
            std::size_t i;
            {
                std::lock_guard lock(mutex);
                if (next == n) return;
                i = next++;
                running[i] = Clock::now();
            }
            const CheckContext ctx(options, pool.executor(), job_stream(*jobs[i].warp, *jobs[i].check, options.seed),
                                   &cancel[i]);
            active[i] = true;
            ThreadPool::set_current_tag(&jobs[i]);
            CheckResult r = run_job_here(jobs[i], ctx);
            ThreadPool::set_current_tag(nullptr);
            active[i] = false;
            std::lock_guard lock(mutex);
            r.seconds = std::chrono::duration<double>(Clock::now() - *running[i]).count();
            if (cancel[i]) {
                r.verdict = Verdict::Error;
                r.summary = "error: over time budget";
                r.message = fmt::format("did not finish within its time budget of {} s (wall time, in-process run)",
                                        jobs[i].check->time_budget(options));
            }
            results[i] = std::move(r);
            running[i].reset();
            ++done;
            if (progress) progress({done, n, jobs[i].check->name(), jobs[i].warp->name(), &results[i]});
            changed.notify_all();
        }
    };
    std::vector<std::jthread> job_threads;
    for (std::size_t t = 0; t < std::min<std::size_t>(threads, n); ++t) job_threads.emplace_back(job_thread);
    std::unique_lock lock(mutex);
    while (done < n) {
        changed.wait_for(lock, std::chrono::milliseconds(50));
        for (std::size_t i = 0; i < n; ++i) {
            const auto budget = std::chrono::duration<double>(jobs[i].check->time_budget(options));
            if (running[i] && Clock::now() - *running[i] > budget) cancel[i] = true;
        }
    }
    lock.unlock();
    job_threads.clear();  // joins
    return results;
}

}  // namespace

std::string rerun_command(const std::string& program, const std::string& case_name, const std::string& check_name,
                          uint64_t seed, uint64_t samples, double max_float_bias) {
    std::string command = fmt::format("{} --filter {} --check {} --seed {} --samples {}", shell_word(program),
                                      shell_quote(case_name), shell_word(check_name), seed, samples);
    if (max_float_bias > 0.0) command += fmt::format(" --max-float-bias {}", max_float_bias);
    return command;
}

RunResult run_jobs(const std::vector<Job>& jobs, const RunOptions& options, const ProgressCallback& progress,
                   const Isolation& isolation) {
    const auto start = Clock::now();
    const unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());

    RunResult run;
    run.info.seed = options.seed;
    run.info.threads = threads;
    run.info.samples = options.samples;
    run.info.strict = options.strict;
    run.info.max_float_bias = options.max_float_bias;
    run.info.compiler = WARPCHECK_COMPILER;
    run.info.machine = machine_description();
    run.info.started_at = utc_now();

    // Only the jobs that apply run; the others become n/a rows in their place.
    std::vector<Job> runnable;
    std::vector<const Check*> checks;  // each once, in order of first use
    for (const Job& job : jobs) {
        if (!job.not_applicable.empty()) continue;
        runnable.push_back(job);
        if (std::find(checks.begin(), checks.end(), job.check) == checks.end()) checks.push_back(job.check);
    }
    for (const Check* check : checks) check->prepare(options);  // before the workers fork: they inherit it
    std::vector<CheckResult> ran =
        isolation.enabled ? run_jobs_isolated(runnable, options, isolation, threads, progress, run.info.abandoned_checks)
                          : run_jobs_in_process(runnable, options, threads, progress);
    run.results.resize(jobs.size());
    for (std::size_t i = 0, k = 0; i < jobs.size(); ++i) {
        if (jobs[i].not_applicable.empty()) {
            run.results[i] = std::move(ran[k++]);
            continue;
        }
        run.results[i].verdict = Verdict::NotApplicable;
        run.results[i].summary = "not applicable: " + jobs[i].not_applicable;
    }
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        CheckResult& r = run.results[i];
        const StreamId stream = job_stream(*jobs[i].warp, *jobs[i].check, options.seed);
        r.case_name = jobs[i].warp->name();
        r.check_name = jobs[i].check->name();
        r.stream_seed = stream.seed;
        r.stream_sequence = stream.sequence;
        r.rerun_command = rerun_command(options.program, r.case_name, r.check_name, options.seed, options.samples,
                                        options.max_float_bias);
    }
    apply_multiple_test_correction(run, options.alpha, options.family_tests.value_or(statistical_tests(jobs)));
    for (std::size_t i = 0; i < jobs.size(); ++i) record_judgement(run.results[i], jobs[i].check->judged_rules());
    // Each check's legend once, in the order its rows first appear: reports explain any check from these.
    for (const Job& job : jobs)
        if (std::none_of(run.info.legends.begin(), run.info.legends.end(),
                         [&](const CheckLegend& l) { return l.check == job.check->name(); }))
            run.info.legends.push_back(job.check->legend());
    run.info.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return run;
}

}  // namespace warpcheck
