#include "validate/run/worker.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <exception>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "reports/terminal_table.h"
#include "validate/run/result_codec.h"
#include "validate/run/runner.h"
#include "validate/run/worker_output.h"
#include "validate/run/worker_supervisor.h"

namespace warpcheck {

uint64_t physical_memory() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    return pages > 0 && page > 0 ? static_cast<uint64_t>(pages) * static_cast<uint64_t>(page) : 0;
}

uint64_t run_memory_budget(const Isolation& isolation, unsigned workers) {
    if (isolation.memory_budget) return *isolation.memory_budget;
    const uint64_t cap = kDefaultWorkerMemory * std::max(1u, workers);
    const uint64_t machine = physical_memory();
    return machine > 0 ? std::min(machine, cap) : cap;
}

uint64_t worker_memory_limit(uint64_t budget, unsigned workers) { return budget / std::max(1u, workers); }

CheckResult run_job_here(const Job& job, const CheckContext& ctx, const std::string& memory_note) {
    auto error = [](std::string message) {
        CheckResult r;
        r.verdict = Verdict::Error;
        r.summary = "error";
        r.message = std::move(message);
        return r;
    };
    try {
        return job.check->run(*job.warp, ctx);
    } catch (const CheckCancelled& e) {
        return error(e.what());
    } catch (const std::bad_alloc&) {
        return error(memory_note.empty() ? "ran out of memory (std::bad_alloc): the warp allocates without bound?"
                                         : "ran out of memory (std::bad_alloc): the warp allocates without bound, "
                                           "or the check needs more than " + memory_note);
    } catch (const std::exception& e) {
        return error(fmt::format("the check could not run: {}", e.what()));
    } catch (...) {
        return error("the check could not run: unknown exception");
    }
}

namespace {

using Clock = std::chrono::steady_clock;

/// A result is at most this long (a larger length is not one a worker wrote).
constexpr uint64_t kMaxResultBytes = uint64_t{1} << 32;

enum Stream { kResult = 0, kStdout = 1, kStderr = 2 };

/// A job in a worker, as the parent sees it: the read ends of its pipes and
/// what came through them.
struct Worker {
    std::size_t job = 0;
    Clock::time_point start;
    int fds[3] = {-1, -1, -1};  // -1 once at end of file or no longer read
    std::string result;         // the length-prefixed result, read no further than its end
    CapturedOutput out, err;
};

/// How many more bytes of the result message to read: its 8-byte length, then
/// that many bytes; 0 once it is complete (or the length is not one a worker wrote).
std::size_t result_bytes_wanted(const std::string& message) {
    uint64_t size = 0;
    if (message.size() < sizeof size) return sizeof size - message.size();
    std::memcpy(&size, message.data(), sizeof size);
    if (size > kMaxResultBytes) return 0;
    return static_cast<std::size_t>(sizeof size + size - message.size());
}

bool result_complete(const std::string& message) {
    uint64_t size = 0;
    if (message.size() < sizeof size) return false;
    std::memcpy(&size, message.data(), sizeof size);
    return size <= kMaxResultBytes && message.size() == sizeof size + size;
}

void close_stream(Worker& w, int s) {
    if (w.fds[s] >= 0) ::close(w.fds[s]);
    w.fds[s] = -1;
}

// Reads what is waiting on stream `s` of `w` (at most `rounds` reads, without
// blocking), up to the result's end; closes it at end of file.
void read_stream(Worker& w, int s, int rounds) {
    char buffer[65536];
    for (int i = 0; i < rounds && w.fds[s] >= 0; ++i) {
        const std::size_t want = s == kResult ? std::min(sizeof buffer, result_bytes_wanted(w.result)) : sizeof buffer;
        if (want == 0) return close_stream(w, s);
        const ssize_t n = ::read(w.fds[s], buffer, want);
        if (n < 0 && (errno == EAGAIN || errno == EINTR)) return;
        if (n <= 0) return close_stream(w, s);
        const std::string_view bytes(buffer, static_cast<std::size_t>(n));
        if (s == kResult) w.result.append(bytes);
        else (s == kStdout ? w.out : w.err).append(bytes);
    }
}

// Three pipes for a job; the parent's read ends do not block.
void make_pipes(int (&read_ends)[3], int (&write_ends)[3]) {
    for (int s = 0; s < 3; ++s) {
        int ends[2];
        if (::pipe2(ends, O_CLOEXEC) != 0) {
            const int error = errno;
            for (int t = 0; t < s; ++t) ::close(read_ends[t]), ::close(write_ends[t]);
            throw std::runtime_error(fmt::format("pipe: {}", std::strerror(error)));
        }
        ::fcntl(ends[0], F_SETFL, O_NONBLOCK);
        read_ends[s] = ends[0];
        write_ends[s] = ends[1];
    }
}

double cpu_seconds(const rusage& usage) {
    return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// Where a check's CPU time budget came from, and how to raise it.
std::string budget_origin(const Job& job, const RunOptions& options) {
    if (options.time_budget_set) return "set by --time-budget";
    if (job.check->time_budget(options) == options.check_time_budget)
        return "the default; --time-budget SECONDS raises it";
    return "this check's own, derived from its work; --time-budget SECONDS replaces it";
}

// Why a worker that went over a time budget was killed: what it used against what.
std::string over_budget_cause(const WorkerEnded& e, const Job& job, const RunOptions& options, int budget) {
    const double cpu = cpu_seconds(e.usage);
    if (e.killed_after_wall_seconds > 0.0) {
        const double limit = (e.killed_after_wall_seconds < kWallHardStopFactor * budget ? kWallBackstopFactor
                                                                                          : kWallHardStopFactor);
        return fmt::format("did not finish within {} s of wall time ({}x its CPU time budget of {} s) while "
                           "using {:.1f} s of CPU time: {} The worker was killed",
                           limit * budget, limit, budget, cpu,
                           limit == kWallBackstopFactor ? "asleep, blocked or stopped?"
                                                        : "a machine too busy to give it CPU time?");
    }
    return fmt::format("over its CPU time budget of {} s ({}): used {:.1f} s of CPU time and was killed. A check "
                       "that is slow but finite passes with a larger budget or fewer --samples; a sampler that "
                       "never terminates exceeds any budget",
                       budget, budget_origin(job, options), cpu);
}

// Why a worker left no result, from how it ended.
std::string cause_of_death(const WorkerEnded& e, const Job& job, const RunOptions& options, bool& over_budget) {
    over_budget = false;
    if (e.fork_errno != 0)
        return fmt::format("could not start a worker process (fork: {})", std::strerror(e.fork_errno));
    const int budget = static_cast<int>(std::ceil(job.check->time_budget(options)));
    const int sig = WIFSIGNALED(e.status) ? WTERMSIG(e.status) : 0;
    over_budget = e.killed_after_wall_seconds > 0.0 || sig == SIGXCPU ||
                  (sig == SIGKILL && cpu_seconds(e.usage) >= budget);
    if (over_budget) return over_budget_cause(e, job, options, budget);
    if (WIFEXITED(e.status) && WEXITSTATUS(e.status) == 0) return "called exit(0) before returning a result";
    if (WIFEXITED(e.status))
        return fmt::format("exited with status {} before returning a result", WEXITSTATUS(e.status));
    if (sig == SIGABRT) return "aborted (SIGABRT)";
    if (sig == SIGKILL) return "killed by signal 9 (SIGKILL): out of memory (the kernel's OOM killer)?";
    return fmt::format("killed by signal {} ({})", sig, signal_name(sig));
}

CheckResult error_result(std::string message, bool over_budget, const Worker& w) {
    CheckResult r;
    r.verdict = Verdict::Error;
    r.message = std::move(message);
    r.summary = over_budget ? "error: over time budget" : "error: worker died";
    r.seconds = std::chrono::duration<double>(Clock::now() - w.start).count();
    return r;
}

// The result a finished worker sent, or an Error result saying how it ended.
CheckResult result_of(const Worker& w, const WorkerEnded& e, const Job& job, const RunOptions& options,
                      bool& over_budget) {
    over_budget = false;
    const bool clean_exit = e.fork_errno == 0 && WIFEXITED(e.status) && WEXITSTATUS(e.status) == 0;
    if (clean_exit && result_complete(w.result))
        if (auto r = decode_result(w.result.substr(sizeof(uint64_t)))) return *r;
    std::string cause = cause_of_death(e, job, options, over_budget);
    return error_result(std::move(cause), over_budget, w);
}

// The warp's output as the row's evidence; an error row also quotes the last
// line the warp wrote to standard error (an assertion's message, often).
void attach_outputs(CheckResult& r, const Worker& w) {
    attach_output(r, w.out, "stdout");
    attach_output(r, w.err, "stderr");
    const std::string last = w.err.last_line();
    if (r.verdict != Verdict::Error || last.empty()) return;
    constexpr std::size_t kQuoted = 240;
    r.message += fmt::format("; its last line on standard error: \"{}{}\"", last.substr(0, kQuoted),
                             last.size() > kQuoted ? "..." : "");
}

/// The memory each worker may use, said the way an out-of-memory row needs it.
std::string memory_note(const Isolation& isolation, uint64_t budget, unsigned workers) {
    if (budget == 0) return {};
    const uint64_t mib = uint64_t{1} << 20;
    const std::string origin = isolation.memory_budget
                                   ? fmt::format("--memory-limit {} MiB", budget / mib)
                                   : fmt::format("the default budget of {} MiB: the machine's physical memory, at "
                                                 "most {} MiB per worker; --memory-limit MIB sets it",
                                                 budget / mib, kDefaultWorkerMemory / mib);
    return fmt::format("the {} MiB of address space each worker may use ({}, shared by the {} workers that run at "
                       "once)",
                       worker_memory_limit(budget, workers) / mib, origin, workers);
}

class WorkerPool {
public:
    WorkerPool(const std::vector<Job>& jobs, const RunOptions& options, const Isolation& isolation, unsigned threads,
               const ProgressCallback& progress)
        : jobs_(jobs), options_(options), progress_(progress), results_(jobs.size()) {
        // One job per thread, each worker single-threaded: jobs are many and
        // short, so this keeps every core busy without a pool per worker.
        workers_ = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(jobs.size())));
        const uint64_t budget = run_memory_budget(isolation, workers_);
        setup_.jobs = &jobs_;
        setup_.options = &options_;
        setup_.threads_per_worker = std::max(1u, threads / workers_);
        setup_.memory_limit = worker_memory_limit(budget, workers_);
        setup_.memory_note = memory_note(isolation, budget, workers_);
    }
    ~WorkerPool() {
        for (Worker& w : running_)
            for (int s = 0; s < 3; ++s) close_stream(w, s);
    }
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    std::vector<CheckResult> run(int& over_budget) {
        supervisor_.emplace(setup_);
        while (next_ < jobs_.size() || !running_.empty()) {
            while (running_.size() < workers_ && next_ < jobs_.size()) start(next_++);
            wait_for_output();
            handle_reports();
        }
        supervisor_.reset();  // waits until every process of the run is gone
        over_budget = over_budget_;
        return std::move(results_);
    }

private:
    void start(std::size_t job) {
        int read_ends[3], write_ends[3];
        make_pipes(read_ends, write_ends);
        Worker w;
        w.job = job;
        w.start = Clock::now();
        std::copy(std::begin(read_ends), std::end(read_ends), w.fds);
        const bool handed_over =
            supervisor_->start(job, write_ends[kResult], write_ends[kStdout], write_ends[kStderr]);
        const int error = errno;
        for (int fd : write_ends) ::close(fd);
        running_.push_back(std::move(w));
        // A supervisor that is gone ends its jobs in handle_reports; one that
        // lives but could not be reached will never report this job.
        if (!handed_over && supervisor_->alive())
            finish(running_.end() - 1, error_result(fmt::format("could not hand the job to the worker supervisor "
                                                                "process ({})",
                                                                std::strerror(error)),
                                                    false, running_.back()));
    }

    // Waits up to 200 ms for a report or output, then reads what the workers sent.
    void wait_for_output() {
        std::vector<pollfd> polls{{supervisor_->fd(), POLLIN, 0}};
        for (const Worker& w : running_)
            for (int fd : w.fds)
                if (fd >= 0) polls.push_back({fd, POLLIN, 0});
        ::poll(polls.data(), polls.size(), 200);
        for (Worker& w : running_)
            for (int s = 0; s < 3; ++s) read_stream(w, s, 1);
    }

    void handle_reports() {
        while (const auto ended = supervisor_->next_report()) {
            const auto it = std::find_if(running_.begin(), running_.end(),
                                         [&](const Worker& w) { return w.job == ended->job; });
            if (it == running_.end()) continue;
            // The worker has ended: all it wrote is in the pipes, whoever else holds them.
            for (int s = 0; s < 3; ++s) read_stream(*it, s, 64);
            bool over_budget = false;
            CheckResult r = result_of(*it, *ended, jobs_[it->job], options_, over_budget);
            over_budget_ += over_budget;
            finish(it, std::move(r));
        }
        if (!supervisor_->alive()) replace_supervisor();
    }

    // A supervisor killed under the run (by a warp that killed its parent, say)
    // took its workers with it: their jobs are error rows, the rest run on.
    void replace_supervisor() {
        if (running_.empty() && ++idle_supervisor_deaths_ > 2)
            throw std::runtime_error("the worker supervisor process " + supervisor_->how_it_ended());
        const std::string message = fmt::format("the worker supervisor process {} while the check ran (did the warp "
                                                "kill its parent?); its worker died with it",
                                                supervisor_->how_it_ended());
        while (!running_.empty()) finish(running_.begin(), error_result(message, false, running_.front()));
        supervisor_.reset();
        supervisor_.emplace(setup_);
    }

    void finish(std::vector<Worker>::iterator it, CheckResult r) {
        attach_outputs(r, *it);
        for (int s = 0; s < 3; ++s) close_stream(*it, s);
        const std::size_t job_index = it->job;
        const Job& job = jobs_[job_index];
        results_[job_index] = std::move(r);
        running_.erase(it);
        ++done_;
        if (progress_) progress_({done_, jobs_.size(), job.check->name(), job.warp->name(), &results_[job_index]});
    }

    const std::vector<Job>& jobs_;
    const RunOptions& options_;
    const ProgressCallback& progress_;
    unsigned workers_ = 1;
    WorkerSetup setup_;
    std::optional<WorkerSupervisor> supervisor_;
    std::vector<CheckResult> results_;
    std::vector<Worker> running_;
    std::size_t next_ = 0, done_ = 0;
    int over_budget_ = 0, idle_supervisor_deaths_ = 0;
};

}  // namespace

std::vector<CheckResult> run_jobs_isolated(const std::vector<Job>& jobs, const RunOptions& options,
                                           const Isolation& isolation, unsigned threads,
                                           const ProgressCallback& progress, int& over_budget) {
    return WorkerPool(jobs, options, isolation, threads, progress).run(over_budget);
}

}  // namespace warpcheck
