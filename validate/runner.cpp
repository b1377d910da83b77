#include "validate/runner.h"

#include <sys/utsname.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "chi2/multiple_testing.h"
#include "warpcheck/version.h"

namespace warpcheck {

StreamId job_stream(const WarpCase& warp, const Check& check, uint64_t seed) {
    return stream_for(warp.name() + "/" + check.name(), seed);
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
        if (!registry.known_flaw(*warp).empty() && !options.include_flawed && !named) continue;
        for (const auto& check : registry.checks()) {
            const bool wanted = check_names.empty() ? check->runs_by_default(options)
                                                    : std::find(check_names.begin(), check_names.end(),
                                                                check->name()) != check_names.end();
            if (wanted && check->applies_to(*warp)) jobs.push_back({warp.get(), check.get()});
        }
    }
    return jobs;
}

void apply_multiple_test_correction(RunResult& run, double family_alpha) {
    int tests = 0;
    for (const auto& r : run.results) tests += r.p_value.has_value();
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

namespace {

CheckResult error_result(std::string message) {
    CheckResult r;
    r.verdict = Verdict::Error;
    r.summary = "error";
    r.message = std::move(message);
    return r;
}

CheckResult run_one_job(const Job& job, const CheckContext& ctx) {
    try {
        return job.check->run(*job.warp, ctx);
    } catch (const CheckCancelled& e) {
        return error_result(e.what());
    } catch (const std::exception& e) {
        return error_result(fmt::format("the check could not run: {}", e.what()));
    } catch (...) {
        return error_result("the check could not run: unknown exception");
    }
}

// Everything the job threads touch lives here, shared with them: a thread that
// is abandoned (stuck in a warp that never returns) keeps it alive on its own.
struct RunState {
    struct Slot {
        std::atomic<bool> cancel{false};
        bool started = false, finished = false, abandoned = false;
        std::chrono::steady_clock::time_point start;
        CheckResult result;
    };

    RunState(const std::vector<Job>& j, const RunOptions& o, unsigned threads)
        : jobs(j), options(o), pool(std::make_shared<ThreadPool>(threads)), slots(j.size()) {}

    std::vector<Job> jobs;
    RunOptions options;
    std::shared_ptr<ThreadPool> pool;
    std::vector<Slot> slots;
    std::mutex mutex;
    std::condition_variable changed;
    std::size_t next = 0;      // next job to hand out
    std::size_t done = 0;      // finished or abandoned
    unsigned live_threads = 0;  // job threads not abandoned and not yet exited
    std::vector<std::size_t> current_job;  // per job thread: the job it runs
};

void job_thread(std::shared_ptr<RunState> state, ProgressCallback progress, std::size_t id) {
    for (;;) {
        std::size_t i;
        {
            std::lock_guard lock(state->mutex);
            if (state->next == state->jobs.size()) {
                --state->live_threads;
                state->changed.notify_all();
                return;
            }
            i = state->next++;
            state->current_job[id] = i;
            state->slots[i].started = true;
            state->slots[i].start = std::chrono::steady_clock::now();
        }
        const Job& job = state->jobs[i];
        auto& slot = state->slots[i];
        const CheckContext ctx(state->options, *state->pool, job_stream(*job.warp, *job.check, state->options.seed),
                               &slot.cancel);
        CheckResult r = run_one_job(job, ctx);
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - slot.start).count();
        std::lock_guard lock(state->mutex);
        if (slot.abandoned) return;  // reported already; a replacement thread took over
        slot.result = std::move(r);
        slot.finished = true;
        ++state->done;
        if (progress) progress(state->done, state->jobs.size(), job.check->name() + " " + job.warp->name());
        state->changed.notify_all();
    }
}

}  // namespace

RunResult run_jobs(const std::vector<Job>& jobs, const RunOptions& options, const ProgressCallback& progress) {
    const auto start = std::chrono::steady_clock::now();
    const unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());

    RunResult run;
    run.info.seed = options.seed;
    run.info.threads = threads;
    run.info.samples = options.samples;
    run.info.compiler = WARPCHECK_COMPILER;
    run.info.machine = machine_description();
    run.info.started_at = utc_now();

    // Jobs run on their own threads, `threads` at a time, while this thread
    // watches the clock: a job over its budget is reported as an error, told
    // to stop, and left behind, and a fresh thread takes its place. Within a
    // job, work is split over the shared pool; a caller always works on its own
    // loop, so jobs progress even when pool threads are stuck.
    auto state = std::make_shared<RunState>(jobs, options, threads);
    std::vector<std::thread> job_threads;
    std::vector<bool> stuck;
    auto spawn = [&] {  // with state->mutex held
        ++state->live_threads;
        state->current_job.push_back(jobs.size());
        stuck.push_back(false);
        job_threads.emplace_back(job_thread, state, progress, job_threads.size());
    };
    const auto budget = std::chrono::duration<double>(options.check_time_budget);
    {
        std::unique_lock lock(state->mutex);
        for (unsigned t = 0; t < std::min<std::size_t>(threads, jobs.size()); ++t) spawn();
        while (state->done < jobs.size() || state->live_threads > 0) {
            // Wake for every finished job, and at least every 50 ms to look at the clock.
            state->changed.wait_for(lock, std::chrono::milliseconds(50));
            const auto now = std::chrono::steady_clock::now();
            for (std::size_t i = 0; i < jobs.size(); ++i) {
                auto& slot = state->slots[i];
                if (!slot.started || slot.finished || slot.abandoned || now - slot.start < budget) continue;
                slot.abandoned = true;
                slot.cancel = true;
                slot.result = error_result(fmt::format(
                    "did not finish within the time budget of {} s (a sampler that never terminates?); "
                    "the check was abandoned",
                    options.check_time_budget));
                slot.result.summary = "error: over time budget";
                slot.result.seconds = options.check_time_budget;
                ++state->done;
                ++run.info.abandoned_checks;
                --state->live_threads;  // the stuck thread no longer counts
                for (std::size_t t = 0; t < job_threads.size(); ++t)
                    if (state->current_job[t] == i) stuck[t] = true;
                if (progress) progress(state->done, jobs.size(), jobs[i].check->name() + " " + jobs[i].warp->name());
                if (state->next < jobs.size()) spawn();
            }
        }
        run.results.reserve(jobs.size());
        for (std::size_t i = 0; i < jobs.size(); ++i) {
            CheckResult r = std::move(state->slots[i].result);
            const StreamId stream = job_stream(*jobs[i].warp, *jobs[i].check, options.seed);
            r.case_name = jobs[i].warp->name();
            r.check_name = jobs[i].check->name();
            r.stream_seed = stream.seed;
            r.stream_sequence = stream.sequence;
            r.rerun_command = fmt::format("validate --filter {} --check {} --seed {} --samples {}",
                                          shell_quote(r.case_name), r.check_name, options.seed, options.samples);
            run.results.push_back(std::move(r));
        }
    }
    for (std::size_t t = 0; t < job_threads.size(); ++t) {
        if (stuck[t]) job_threads[t].detach();  // it holds `state`, so what it uses stays alive
        else job_threads[t].join();
    }

    apply_multiple_test_correction(run, options.alpha);
    run.info.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return run;
}

}  // namespace warpcheck
