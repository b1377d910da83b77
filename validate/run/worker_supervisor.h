// The processes of an isolated run. `validate` forks one supervisor process per
// run; the supervisor forks a worker per job and is the only process that
// waits for them. Between the three:
//
//   validate --(socket: "run job i", with the job's three pipe ends)--> supervisor --fork--> worker
//   validate <--(socket: "job i ended: wait status, CPU time")--------- supervisor
//   validate <--(pipes: result, stdout, stderr of job i)----------------------------------- worker
//
// What this buys, whatever a warp does in its worker:
// - Each worker leads its own process group, and a child subreaper holds the
//   orphans of its processes (a daemon that double-forks and calls setsid()
//   included): when the worker ends, for any reason, the supervisor kills its
//   group and every process that was left to it. Nothing a check started
//   outlives the check.
// - The supervisor is in a process group of its own (a terminal's Ctrl-C
//   reaches `validate` only) and watches the socket: when `validate` exits for
//   any reason, SIGKILL included, the socket's end of file makes it kill every
//   worker and every descendant, then exit. Workers die with the supervisor
//   (PR_SET_PDEATHSIG), and a signal that would end it (SIGTERM, SIGINT, SIGHUP,
//   SIGQUIT) makes it clean up first.
// - `validate` never waits for end of file on a pipe that a warp's child may
//   hold: the supervisor's report says when the worker has ended, and all it
//   wrote is in the pipes by then.
#pragma once

#include <sys/resource.h>
#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "validate/checks/check.h"

namespace warpcheck {

struct Job;

/// Everything a worker needs, in the memory that the supervisor and its workers
/// inherit from `validate` (the jobs, their warps and checks included).
struct WorkerSetup {
    const std::vector<Job>* jobs = nullptr;
    const RunOptions* options = nullptr;
    uint64_t memory_limit = 0;  ///< RLIMIT_AS of each worker in bytes (0: none)
    std::string memory_note;    ///< how memory_limit was set, for an out-of-memory message
    unsigned threads_per_worker = 1;
};

/// A worker's end, as the supervisor saw it.
struct WorkerEnded {
    uint64_t job = 0;
    int status = 0;      ///< as wait4 reports it
    rusage usage{};      ///< the worker's CPU time
    /// Killed by the wall-clock backstop (below): the wall time it had then, in
    /// seconds; 0 otherwise.
    double killed_after_wall_seconds = 0.0;
    int fork_errno = 0;  ///< non-zero: the worker could not be started at all
};

/// The wall-clock backstop. A worker asleep (or blocked, or stopped) uses no CPU
/// time, so its CPU limit never ends it: after this many times its CPU budget
/// in wall time, a worker that used less than kWorkingCoreShare of a core over
/// the last second is killed. One that uses more is working, however slowly a
/// busy machine lets it (a spinning warp once got 4% of a core there), and is
/// left to its CPU limit, up to kWallHardStopFactor times its budget.
constexpr double kWallBackstopFactor = 10.0;
constexpr double kWallHardStopFactor = 30.0;
/// 1% of a core: a sleeping, blocked or stopped process uses next to none; a
/// working one gets about cores/load of a core, 1% at a load of 200 on 2 cores.
constexpr double kWorkingCoreShare = 0.01;

/// The backstop's rule: whether a worker that has run for `wall_seconds` of
/// its `budget` CPU seconds, and used `recent_core_share` of a core over the
/// last second, is killed for wall time.
bool past_wall_backstop(double wall_seconds, double recent_core_share, int budget);

/// The budget of job `job` in CPU seconds as its worker's limit applies it:
/// the check's own budget (Check::time_budget), rounded up to whole seconds.
int worker_cpu_budget(const WorkerSetup& setup, std::size_t job);

/// "SIGSEGV" for 11, "signal 99" for a number without a name.
std::string signal_name(int sig);

/// The supervisor process of one run, as `validate` holds it.
class WorkerSupervisor {
public:
    /// Forks the supervisor. `setup` must outlive this object.
    explicit WorkerSupervisor(const WorkerSetup& setup);
    /// Ends the supervisor, which first kills every worker and descendant, and
    /// collects it (within a few seconds; then it is killed).
    ~WorkerSupervisor();
    WorkerSupervisor(const WorkerSupervisor&) = delete;
    WorkerSupervisor& operator=(const WorkerSupervisor&) = delete;

    /// Poll this for reports.
    int fd() const { return socket_; }
    /// Asks for job `job` to run in a new worker writing its result, standard
    /// output and standard error to the given pipe ends (which this call does
    /// not close). False if the supervisor is gone.
    bool start(std::size_t job, int result_fd, int stdout_fd, int stderr_fd);
    /// The next report if one is waiting; nullopt if none is (or the supervisor
    /// is gone: see alive()).
    std::optional<WorkerEnded> next_report();
    /// Whether the supervisor still serves. A stopped supervisor (SIGSTOP from a
    /// warp) is continued here.
    bool alive();
    /// How a supervisor that is no longer alive ended, for the rows it leaves
    /// (collected first: killed if it has not ended within 2 s).
    std::string how_it_ended();

private:
    void collect(std::chrono::seconds patience);

    pid_t pid_ = -1;
    int socket_ = -1;
    bool gone_ = false;
    std::optional<int> exit_status_;  // once collected
};

}  // namespace warpcheck
