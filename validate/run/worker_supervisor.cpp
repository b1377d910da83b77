#include "validate/run/worker_supervisor.h"

#include <dirent.h>
#include <fcntl.h>
#include <malloc.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <stdexcept>

#include <fmt/format.h>

#include "validate/run/asan.h"
#include "validate/run/result_codec.h"
#include "validate/run/runner.h"
#include "validate/run/thread_pool.h"
#include "validate/run/worker.h"


namespace warpcheck {

int worker_cpu_budget(const WorkerSetup& setup, std::size_t job) {
    return static_cast<int>(std::ceil((*setup.jobs)[job].check->time_budget(*setup.options)));
}

bool past_wall_backstop(double wall_seconds, double recent_core_share, int budget) {
    if (wall_seconds >= kWallHardStopFactor * budget) return true;
    return wall_seconds >= kWallBackstopFactor * budget && !(recent_core_share >= kWorkingCoreShare);
}

std::string signal_name(int sig) {
    const char* abbrev = sigabbrev_np(sig);
    return abbrev ? fmt::format("SIG{}", abbrev) : fmt::format("signal {}", sig);
}

namespace {

using Clock = std::chrono::steady_clock;

/// validate -> supervisor: run this job (the message carries its three pipe ends).
struct StartCommand {
    uint64_t job = 0;
};

// ---------------------------------------------------------------- a worker

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
void limit_worker([[maybe_unused]] const WorkerSetup& setup, int cpu_budget) {
    const rlimit cpu_limit{static_cast<rlim_t>(cpu_budget), static_cast<rlim_t>(cpu_budget) + 1};
    setrlimit(RLIMIT_CPU, &cpu_limit);
    const rlimit no_core{0, 0};  // a warp that crashes in every job leaves no core file per job
    setrlimit(RLIMIT_CORE, &no_core);
#ifndef WARPCHECK_ASAN
    if (setup.memory_limit > 0) {
        const rlimit as_limit{setup.memory_limit, setup.memory_limit};
        setrlimit(RLIMIT_AS, &as_limit);
    }
#endif
}

// A worker lives for one job: memory its check frees stays in the process for
// the check's next allocation. By default glibc maps large blocks (above 128
// KiB at first) afresh each time and returns the heap's free top, so every
// chunk's buffers were faulted in and zeroed by the kernel again (4 of the 38
// CPU seconds of the non-BSDF jobs of validate --all were the kernel's, 2
// with this). Blocks up to 32 MiB (glibc's largest threshold) now come from
// the heap, which is never trimmed.
void keep_freed_memory() {
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, INT_MAX);
}

// Standard input from /dev/null (a warp never reads the user's terminal),
// standard output and error into the job's pipes. Returns the result pipe,
// moved above the standard streams and closed on exec (a program the warp runs
// gets the output pipes, not the result pipe).
int redirect_streams(const int (&fds)[3]) {
    int high[3];
    for (int i = 0; i < 3; ++i) {
        high[i] = ::fcntl(fds[i], F_DUPFD_CLOEXEC, 3);
        ::close(fds[i]);
    }
    const int null = ::open("/dev/null", O_RDONLY);
    if (null > 0) {
        ::dup2(null, STDIN_FILENO);
        ::close(null);
    }
    ::dup2(high[1], STDOUT_FILENO);
    ::dup2(high[2], STDERR_FILENO);
    ::close(high[1]);
    ::close(high[2]);
    return high[0];
}

// A worker's first steps: a process group of its own, death with the
// supervisor, custody of its processes' orphans, default signal handling and
// its own standard streams. False if the supervisor is already gone.
bool enter_worker(pid_t supervisor, const int (&fds)[3], std::initializer_list<int> supervisor_fds, int& result_fd) {
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != supervisor) return false;  // it died before the line above
    ::prctl(PR_SET_CHILD_SUBREAPER, 1);
    for (int sig : {SIGTERM, SIGINT, SIGHUP, SIGQUIT, SIGCHLD}) std::signal(sig, SIG_DFL);
    for (int fd : supervisor_fds) ::close(fd);
    result_fd = redirect_streams(fds);
    return true;
}

// The body of a worker process: run the job, send the result as its length and
// its bytes, leave without running the parent's atexit handlers or destructors.
[[noreturn]] void worker_main(const WorkerSetup& setup, std::size_t index, int result_fd) {
    const Job& job = (*setup.jobs)[index];
    RunOptions options = *setup.options;
    options.check_time_budget = job.check->time_budget(*setup.options);
    limit_worker(setup, worker_cpu_budget(setup, index));
    keep_freed_memory();
    // Line by line, as on a terminal: what a warp printed reaches its row even
    // if it crashes later. (The parent flushed stdout before forking.)
    std::setvbuf(stdout, nullptr, _IOLBF, BUFSIZ);
    int status = 0;
    try {
        ThreadPool pool(setup.threads_per_worker);
        const auto start = Clock::now();
        const CheckContext ctx(options, pool.executor(), job_stream(*job.warp, *job.check, options.seed));
        CheckResult r = run_job_here(job, ctx, setup.memory_note);
        r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
        const std::string bytes = encode_result(r);
        std::cout.flush();
        std::cerr.flush();
        std::fflush(nullptr);
        const uint64_t size = bytes.size();
        if (!write_all(result_fd, &size, sizeof size) || !write_all(result_fd, bytes.data(), bytes.size())) status = 3;
    } catch (...) {
        status = 3;  // could not even build the result (no memory left?)
    }
    ::_exit(status);
}

// ---------------------------------------------------------- the supervisor

volatile std::sig_atomic_t g_stop = 0;
int g_wake_fd = -1;  // write end of the supervisor's self-pipe

extern "C" void wake_supervisor(int sig) {
    const int saved = errno;
    if (sig != SIGCHLD) g_stop = 1;
    const char byte = 0;
    (void)!::write(g_wake_fd, &byte, 1);
    errno = saved;
}

Clock::duration seconds(double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

/// The CPU time a process has used so far, all its threads (0 if unknown).
double process_cpu_seconds(pid_t pid) {
    clockid_t clock{};
    timespec t{};
    if (::clock_getcpuclockid(pid, &clock) != 0 || ::clock_gettime(clock, &t) != 0) return 0.0;
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// The direct children of this process (single-threaded: its one task).
std::vector<pid_t> children_of_self() {
    std::vector<pid_t> children;
    std::ifstream list(fmt::format("/proc/self/task/{}/children", ::getpid()));
    if (list) {
        for (pid_t pid = 0; list >> pid;) children.push_back(pid);
        return children;
    }
    // A kernel without CONFIG_PROC_CHILDREN: every process's parent, from /proc.
    DIR* proc = ::opendir("/proc");
    for (dirent* entry = proc ? ::readdir(proc) : nullptr; entry; entry = ::readdir(proc)) {
        const pid_t pid = std::atoi(entry->d_name);
        std::ifstream stat(fmt::format("/proc/{}/stat", pid));
        std::string text((std::istreambuf_iterator<char>(stat)), {});
        const auto paren = text.rfind(')');  // the name may hold spaces and parentheses
        char state = 0;
        pid_t parent = 0;
        if (pid > 0 && paren != std::string::npos &&
            std::sscanf(text.c_str() + paren + 1, " %c %d", &state, &parent) == 2 && parent == ::getpid())
            children.push_back(pid);
    }
    if (proc) ::closedir(proc);
    return children;
}

class Supervisor {
public:
    Supervisor(const WorkerSetup& setup, int socket) : setup_(setup), socket_(socket), self_(::getpid()) {}
    [[noreturn]] void run();

private:
    struct Running {
        pid_t pid = -1;
        std::size_t job = 0;
        Clock::time_point start;
        Clock::time_point next_look;  // when the wall-clock backstop looks at it next
        Clock::time_point last_look;  // and when it looked last, seeing this CPU time
        double cpu_at_last_look = 0.0;
        int budget = 1;  // CPU seconds
        double killed_after_wall_seconds = 0.0;
    };

    void enter();
    bool serve_command();
    void start_worker(std::size_t job, const int (&fds)[3]);
    void enforce_backstops();
    void collect_ended();
    void kill_strays();
    void shut_down();
    int poll_timeout_ms() const;
    void report(const WorkerEnded& ended) { (void)::send(socket_, &ended, sizeof ended, MSG_NOSIGNAL); }

    const WorkerSetup& setup_;
    int socket_;
    pid_t self_;
    int wake_[2] = {-1, -1};
    std::vector<Running> running_;
};

// A process group of its own (away from the terminal's signals), the child
// subreaper of everything its workers start, and signals that wake its loop.
void Supervisor::enter() {
    ::setpgid(0, 0);
    ::prctl(PR_SET_CHILD_SUBREAPER, 1);
    if (::pipe2(wake_, O_CLOEXEC | O_NONBLOCK) != 0) ::_exit(5);
    g_wake_fd = wake_[1];
    struct sigaction action {};
    action.sa_handler = wake_supervisor;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    for (int sig : {SIGTERM, SIGINT, SIGHUP, SIGQUIT, SIGCHLD}) sigaction(sig, &action, nullptr);
}

void Supervisor::run() {
    enter();
    bool serving = true;
    while (serving && !g_stop) {
        pollfd polls[2] = {{socket_, POLLIN, 0}, {wake_[0], POLLIN, 0}};
        if (::poll(polls, 2, poll_timeout_ms()) > 0) {
            char drain[64];
            while (::read(wake_[0], drain, sizeof drain) > 0) {
            }
            // End of file: validate is done, or gone (whatever ended it).
            if (polls[0].revents & (POLLIN | POLLHUP | POLLERR)) serving = serve_command();
        }
        enforce_backstops();
        collect_ended();
    }
    shut_down();
    ::_exit(0);
}

int Supervisor::poll_timeout_ms() const {
    auto timeout = std::chrono::milliseconds(1000);
    for (const Running& w : running_)
        if (w.killed_after_wall_seconds == 0.0)
            timeout = std::min(timeout, std::chrono::ceil<std::chrono::milliseconds>(w.next_look - Clock::now()));
    return static_cast<int>(std::max<std::chrono::milliseconds::rep>(timeout.count(), 0));
}

// One command from validate; false at end of file.
bool Supervisor::serve_command() {
    StartCommand command;
    iovec io{&command, sizeof command};
    alignas(cmsghdr) char control[CMSG_SPACE(3 * sizeof(int))];
    msghdr message{};
    message.msg_iov = &io;
    message.msg_iovlen = 1;
    message.msg_control = control;
    message.msg_controllen = sizeof control;
    const ssize_t n = ::recvmsg(socket_, &message, MSG_CMSG_CLOEXEC | MSG_DONTWAIT);
    if (n < 0) return errno == EINTR || errno == EAGAIN;
    if (n == 0) return false;
    const cmsghdr* fds_message = CMSG_FIRSTHDR(&message);
    if (!fds_message || fds_message->cmsg_type != SCM_RIGHTS || fds_message->cmsg_len != CMSG_LEN(3 * sizeof(int)))
        return true;  // not a command of validate's
    int fds[3];
    std::memcpy(fds, CMSG_DATA(fds_message), sizeof fds);
    if (n == sizeof command && command.job < setup_.jobs->size()) start_worker(command.job, fds);
    for (int fd : fds) ::close(fd);
    return true;
}

void Supervisor::start_worker(std::size_t job, const int (&fds)[3]) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        int result_fd = -1;
        if (!enter_worker(self_, fds, {socket_, wake_[0], wake_[1]}, result_fd)) ::_exit(4);
        worker_main(setup_, job, result_fd);
    }
    if (pid < 0) {
        WorkerEnded ended;
        ended.job = job;
        ended.fork_errno = errno;
        report(ended);
        return;
    }
    ::setpgid(pid, pid);  // as the worker does: whichever runs first, the group exists before a kill
    const int budget = worker_cpu_budget(setup_, job);
    const auto now = Clock::now();
    // The first look is a second before the backstop, so that the second has
    // the CPU time of the last second to judge by.
    running_.push_back({pid, job, now, now + seconds(kWallBackstopFactor * budget - 1.0), now, 0.0, budget, 0.0});
}

void Supervisor::enforce_backstops() {
    const auto now = Clock::now();
    for (Running& w : running_) {
        if (w.killed_after_wall_seconds > 0.0 || now < w.next_look) continue;
        const double wall = std::chrono::duration<double>(now - w.start).count();
        const double cpu = process_cpu_seconds(w.pid);
        const double share = (cpu - w.cpu_at_last_look) / std::chrono::duration<double>(now - w.last_look).count();
        if (!past_wall_backstop(wall, share, w.budget)) {  // not yet, or working: its CPU limit will end it
            w.last_look = now;
            w.cpu_at_last_look = cpu;
            w.next_look = now + std::chrono::seconds(1);
            continue;
        }
        ::kill(-w.pid, SIGKILL);
        ::kill(w.pid, SIGKILL);  // should the warp have left its group
        w.killed_after_wall_seconds = wall;
    }
}

// Collects every child that ended. A worker's end is its job's end: its
// process group and whatever was left to this subreaper are killed before the
// report, so the next job never meets this one's processes.
void Supervisor::collect_ended() {
    bool collected = false;
    for (;;) {
        siginfo_t info{};
        // WNOWAIT: the pid stays taken (and its group's id with it) until the kill.
        if (::waitid(P_ALL, 0, &info, WEXITED | WNOHANG | WNOWAIT) != 0 || info.si_pid == 0) break;
        const pid_t pid = info.si_pid;
        ::kill(-pid, SIGKILL);
        WorkerEnded ended;
        if (::wait4(pid, &ended.status, 0, &ended.usage) != pid) break;
        collected = true;
        const auto w = std::find_if(running_.begin(), running_.end(), [&](const Running& r) { return r.pid == pid; });
        if (w == running_.end()) continue;  // a stray, killed before
        ended.job = w->job;
        ended.killed_after_wall_seconds = w->killed_after_wall_seconds;
        running_.erase(w);
        kill_strays();
        report(ended);
    }
    if (collected) kill_strays();  // a stray's end may leave its own children to this process
}

// Every child that is not a running worker was left here by a process that
// ended (while a worker runs, its own orphans go to it, a subreaper too).
void Supervisor::kill_strays() {
    for (const pid_t pid : children_of_self()) {
        if (std::any_of(running_.begin(), running_.end(), [&](const Running& r) { return r.pid == pid; })) continue;
        ::kill(-pid, SIGKILL);  // the group it may lead (setsid): pids of living children are never reused
        ::kill(pid, SIGKILL);
    }
}

// Kills every worker, every process they left and those processes' groups,
// until no child is left (or a few seconds have passed: a process in an
// uninterruptible sleep dies when it wakes).
void Supervisor::shut_down() {
    const auto give_up = Clock::now() + std::chrono::seconds(5);
    for (;;) {
        for (const pid_t pid : children_of_self()) {
            ::kill(-pid, SIGKILL);
            ::kill(pid, SIGKILL);
        }
        pid_t collected = 0;
        while ((collected = ::waitpid(-1, nullptr, WNOHANG)) > 0) {
        }
        if ((collected < 0 && errno == ECHILD) || Clock::now() > give_up) return;
        ::poll(nullptr, 0, 5);
    }
}

}  // namespace

// ------------------------------------------------------ validate's side

WorkerSupervisor::WorkerSupervisor(const WorkerSetup& setup) {
    int ends[2];
    if (::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, ends) != 0)
        throw std::runtime_error(fmt::format("socketpair: {}", std::strerror(errno)));
    // Buffered output would be written twice if a warp calls exit() in a worker.
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    pid_ = ::fork();
    if (pid_ < 0) {
        const int error = errno;
        ::close(ends[0]);
        ::close(ends[1]);
        throw std::runtime_error(fmt::format("fork: {}", std::strerror(error)));
    }
    if (pid_ == 0) {
        ::close(ends[0]);
        try {
            Supervisor(setup, ends[1]).run();
        } catch (...) {
        }
        ::_exit(5);
    }
    ::close(ends[1]);
    socket_ = ends[0];
}

WorkerSupervisor::~WorkerSupervisor() {
    ::close(socket_);  // its end of file: the supervisor kills what is left and exits
    collect(std::chrono::seconds(10));
}

void WorkerSupervisor::collect(std::chrono::seconds patience) {
    if (exit_status_) return;
    ::kill(pid_, SIGCONT);
    const auto give_up = Clock::now() + patience;
    int status = 0;
    pid_t r = 0;
    while ((r = ::waitpid(pid_, &status, WNOHANG)) == 0 && Clock::now() < give_up) ::poll(nullptr, 0, 2);
    if (r == 0) {
        ::kill(pid_, SIGKILL);
        r = ::waitpid(pid_, &status, 0);
    }
    exit_status_ = r == pid_ ? status : 0;
    gone_ = true;
}

bool WorkerSupervisor::start(std::size_t job, int result_fd, int stdout_fd, int stderr_fd) {
    StartCommand command{job};
    iovec io{&command, sizeof command};
    alignas(cmsghdr) char control[CMSG_SPACE(3 * sizeof(int))] = {};
    msghdr message{};
    message.msg_iov = &io;
    message.msg_iovlen = 1;
    message.msg_control = control;
    message.msg_controllen = sizeof control;
    cmsghdr* fds_message = CMSG_FIRSTHDR(&message);
    fds_message->cmsg_level = SOL_SOCKET;
    fds_message->cmsg_type = SCM_RIGHTS;
    fds_message->cmsg_len = CMSG_LEN(3 * sizeof(int));
    const int fds[3] = {result_fd, stdout_fd, stderr_fd};
    std::memcpy(CMSG_DATA(fds_message), fds, sizeof fds);
    ssize_t n = 0;
    do n = ::sendmsg(socket_, &message, MSG_NOSIGNAL);
    while (n < 0 && errno == EINTR);
    return n == static_cast<ssize_t>(sizeof command);
}

std::optional<WorkerEnded> WorkerSupervisor::next_report() {
    WorkerEnded ended;
    const ssize_t n = ::recv(socket_, &ended, sizeof ended, MSG_DONTWAIT);
    if (n == static_cast<ssize_t>(sizeof ended)) return ended;
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) gone_ = true;
    return std::nullopt;
}

bool WorkerSupervisor::alive() {
    if (exit_status_) return false;
    int status = 0;
    const pid_t r = ::waitpid(pid_, &status, WNOHANG | WUNTRACED);
    if (r == pid_ && WIFSTOPPED(status)) {
        ::kill(pid_, SIGCONT);  // stopped by a warp (kill(getppid(), SIGSTOP)): it serves on
    } else if (r == pid_ || (r < 0 && errno == ECHILD)) {
        exit_status_ = r == pid_ ? status : 0;
        gone_ = true;
    }
    return !gone_;
}

std::string WorkerSupervisor::how_it_ended() {
    collect(std::chrono::seconds(2));
    if (WIFSIGNALED(*exit_status_)) {
        const int sig = WTERMSIG(*exit_status_);
        return fmt::format("was killed by signal {} ({})", sig, signal_name(sig));
    }
    return fmt::format("exited with status {}", WEXITSTATUS(*exit_status_));
}

}  // namespace warpcheck
