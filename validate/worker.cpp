#include "validate/worker.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include <fmt/format.h>

#include "validate/result_codec.h"
#include "validate/runner.h"

#if defined(__SANITIZE_ADDRESS__)
#define WARPCHECK_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define WARPCHECK_ASAN 1
#endif
#endif

namespace warpcheck {

CheckResult run_job_here(const Job& job, const CheckContext& ctx) {
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
        return error("ran out of memory (std::bad_alloc): the warp allocates without bound, or the memory limit "
                     "(--memory-limit) is too small");
    } catch (const std::exception& e) {
        return error(fmt::format("the check could not run: {}", e.what()));
    } catch (...) {
        return error("the check could not run: unknown exception");
    }
}

namespace {

using Clock = std::chrono::steady_clock;

// A worker that sleeps (or blocks) uses no CPU time; after this many times its
// CPU budget in wall time it is killed all the same. Generous, because on a busy
// machine a worker gets a fraction of a core: at 10x, a check over its CPU budget
// is still caught by the CPU limit with a tenth of a core.
constexpr double kWallBackstopFactor = 10.0;

bool write_all(int fd, const void* data, std::size_t size) {
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        p += n;
        size -= static_cast<std::size_t>(n);
    }
    return true;
}

// The worker's limits. RLIMIT_CPU counts the CPU time of all its threads: past
// the soft limit the kernel sends SIGXCPU, one second later SIGKILL.
void limit_worker(const RunOptions& options, const Isolation& isolation) {
    const auto cpu = static_cast<rlim_t>(std::ceil(options.check_time_budget));
    const rlimit cpu_limit{cpu, cpu + 1};
    setrlimit(RLIMIT_CPU, &cpu_limit);
#ifndef WARPCHECK_ASAN
    if (isolation.memory_limit > 0) {
        const rlimit as_limit{isolation.memory_limit, isolation.memory_limit};
        setrlimit(RLIMIT_AS, &as_limit);
    }
#else
    (void)isolation;
#endif
}

// The run's options as one job sees them: its check's own time budget
// (Check::time_budget: the full sweeps default to one derived from their work).
RunOptions budgeted(const Job& job, const RunOptions& options) {
    RunOptions o = options;
    o.check_time_budget = job.check->time_budget(options);
    return o;
}

// The body of a worker process: run the job, send the result as its length and
// its bytes, leave without running the parent's atexit handlers or destructors.
[[noreturn]] void worker_main(const Job& job, const RunOptions& options, const Isolation& isolation,
                              unsigned threads, int fd) {
    limit_worker(options, isolation);
    int status = 0;
    try {
        ThreadPool pool(threads);
        const auto start = Clock::now();
        const CheckContext ctx(options, pool, job_stream(*job.warp, *job.check, options.seed));
        CheckResult r = run_job_here(job, ctx);
        r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
        const std::string bytes = encode_result(r);
        const uint64_t size = bytes.size();
        if (!write_all(fd, &size, sizeof size) || !write_all(fd, bytes.data(), bytes.size())) status = 3;
    } catch (...) {
        status = 3;  // could not even build the result (no memory left?)
    }
    _exit(status);
}

struct Worker {
    pid_t pid = -1;
    int fd = -1;  // read end of the result pipe; -1 once at end of file
    std::size_t job = 0;
    Clock::time_point start;
    bool killed_for_wall_time = false;
    std::string bytes;
};

std::string signal_name(int sig) {
    const char* abbrev = sigabbrev_np(sig);
    return abbrev ? fmt::format("SIG{}", abbrev) : fmt::format("signal {}", sig);
}

// Why a worker left no result, from how it ended.
std::string cause_of_death(const Worker& w, int status, const rusage& usage, const RunOptions& options,
                           bool& over_budget) {
    const double cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                       1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
    const int budget = static_cast<int>(std::ceil(options.check_time_budget));
    over_budget = true;
    if (w.killed_for_wall_time)
        return fmt::format("did not finish within {} s of wall time ({}x its CPU time budget of {} s) while "
                           "using {:.1f} s of CPU time: asleep or blocked? The worker was killed",
                           kWallBackstopFactor * budget, kWallBackstopFactor, budget, cpu);
    if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGXCPU || (WTERMSIG(status) == SIGKILL && cpu >= budget)))
        return fmt::format("over its CPU time budget of {} s (a sampler that never terminates?); the worker was "
                           "killed",
                           budget);
    over_budget = false;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "called exit(0) before returning a result";
    if (WIFEXITED(status))
        return fmt::format("exited with status {} before returning a result", WEXITSTATUS(status));
    const int sig = WTERMSIG(status);
    if (sig == SIGABRT) return "aborted (SIGABRT)";
    if (sig == SIGKILL) return "killed by signal 9 (SIGKILL): out of memory (the kernel's OOM killer)?";
    return fmt::format("killed by signal {} ({})", sig, signal_name(sig));
}

// The result a finished worker sent, or an Error result saying how it died.
CheckResult result_of(const Worker& w, int status, const rusage& usage, const RunOptions& options,
                      bool& over_budget) {
    over_budget = false;
    uint64_t size = 0;
    if (w.bytes.size() >= sizeof size) std::memcpy(&size, w.bytes.data(), sizeof size);
    const bool complete = w.bytes.size() >= sizeof size && w.bytes.size() - sizeof size == size;
    if (complete && WIFEXITED(status) && WEXITSTATUS(status) == 0)
        if (auto r = decode_result(w.bytes.substr(sizeof size))) return *r;
    CheckResult r;
    r.verdict = Verdict::Error;
    r.message = cause_of_death(w, status, usage, options, over_budget);
    r.summary = over_budget ? "error: over time budget" : "error: worker died";
    r.seconds = std::chrono::duration<double>(Clock::now() - w.start).count();
    return r;
}

class WorkerPool {
public:
    WorkerPool(const std::vector<Job>& jobs, const RunOptions& options, const Isolation& isolation, unsigned threads,
               const ProgressCallback& progress)
        : jobs_(jobs), options_(options), isolation_(isolation), progress_(progress), results_(jobs.size()) {
        // One job per thread, each worker single-threaded: jobs are many and
        // short, so this keeps every core busy without a pool per worker.
        workers_ = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(jobs.size())));
        threads_per_worker_ = std::max(1u, threads / workers_);
    }

    std::vector<CheckResult> run(int& over_budget) {
        while (next_ < jobs_.size() || !running_.empty()) {
            while (running_.size() < workers_ && next_ < jobs_.size()) start(next_++);
            wait_for_output();
            reap();
        }
        over_budget = over_budget_;
        return std::move(results_);
    }

private:
    void start(std::size_t job) {
        int fds[2];
        if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error(fmt::format("pipe: {}", std::strerror(errno)));
        // Buffered output would be written twice if a warp calls exit() in the worker.
        std::cout.flush();
        std::cerr.flush();
        std::fflush(nullptr);
        const pid_t pid = fork();
        if (pid < 0) throw std::runtime_error(fmt::format("fork: {}", std::strerror(errno)));
        if (pid == 0) {
            ::close(fds[0]);
            worker_main(jobs_[job], budgeted(jobs_[job], options_), isolation_, threads_per_worker_, fds[1]);
        }
        ::close(fds[1]);
        running_.push_back({pid, fds[0], job, Clock::now(), false, {}});
    }

    // Reads what the workers sent; returns after at most 50 ms, or 1 ms while a
    // worker that closed its pipe is still to be collected.
    void wait_for_output() {
        std::vector<pollfd> polls;
        for (const auto& w : running_)
            if (w.fd >= 0) polls.push_back({w.fd, POLLIN, 0});
        const int timeout_ms = polls.size() < running_.size() ? 1 : 50;
        if (::poll(polls.data(), polls.size(), timeout_ms) <= 0) return;
        for (auto& w : running_) {
            if (w.fd < 0) continue;
            const auto p = std::find_if(polls.begin(), polls.end(), [&](const pollfd& q) { return q.fd == w.fd; });
            if (!(p->revents & (POLLIN | POLLHUP | POLLERR))) continue;
            char buffer[65536];
            const ssize_t n = ::read(w.fd, buffer, sizeof buffer);
            if (n > 0) w.bytes.append(buffer, static_cast<std::size_t>(n));
            if (n == 0 || (n < 0 && errno != EINTR && errno != EAGAIN)) {
                ::close(w.fd);
                w.fd = -1;
            }
        }
    }

    // Collects the workers that ended; kills those past the wall-clock backstop.
    void reap() {
        for (auto it = running_.begin(); it != running_.end();) {
            const RunOptions job_options = budgeted(jobs_[it->job], options_);
            const auto backstop = std::chrono::duration<double>(kWallBackstopFactor *
                                                                std::ceil(job_options.check_time_budget));
            if (!it->killed_for_wall_time && Clock::now() - it->start > backstop) {
                ::kill(it->pid, SIGKILL);
                it->killed_for_wall_time = true;
            }
            int status = 0;
            rusage usage{};
            // A worker is done once it has exited and its pipe is drained.
            if (it->fd >= 0 || ::wait4(it->pid, &status, WNOHANG, &usage) != it->pid) {
                ++it;
                continue;
            }
            bool over_budget = false;
            results_[it->job] = result_of(*it, status, usage, job_options, over_budget);
            over_budget_ += over_budget;
            ++done_;
            if (progress_)
                progress_({done_, jobs_.size(), jobs_[it->job].check->name(), jobs_[it->job].warp->name(),
                           &results_[it->job]});
            it = running_.erase(it);
        }
    }

    const std::vector<Job>& jobs_;
    const RunOptions& options_;
    const Isolation& isolation_;
    const ProgressCallback& progress_;
    unsigned workers_ = 1, threads_per_worker_ = 1;
    std::vector<CheckResult> results_;
    std::vector<Worker> running_;
    std::size_t next_ = 0, done_ = 0;
    int over_budget_ = 0;
};

}  // namespace

std::vector<CheckResult> run_jobs_isolated(const std::vector<Job>& jobs, const RunOptions& options,
                                           const Isolation& isolation, unsigned threads,
                                           const ProgressCallback& progress, int& over_budget) {
    return WorkerPool(jobs, options, isolation, threads, progress).run(over_budget);
}

}  // namespace warpcheck
