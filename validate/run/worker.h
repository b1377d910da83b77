// Isolated jobs: each (case, check) job runs in a worker process, so a warp
// that crashes, aborts, calls exit(), spins forever, allocates without bound,
// prints, or starts processes of its own costs one ERROR row (or a table of its
// output) instead of the run. The parent stays single-threaded (it forks, so it
// must): it hands jobs to a supervisor process (validate/run/worker_supervisor.h),
// which forks the workers, and reads their results (validate/run/result_codec.h)
// and their output back over pipes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "reports/progress_callback.h"
#include "reports/result.h"
#include "validate/checks/check.h"
#include "validate/run/job.h"

namespace warpcheck {

/// How the runner keeps warps apart from the run.
struct Isolation {
    /// Run each job in a worker process. Off: jobs run on threads of this
    /// process (for debuggers), where a budget can only ask a check to stop.
    bool enabled = false;
    /// The address space (RLIMIT_AS) in bytes that the run's workers may hold
    /// together: the workers that run at once share it equally, so together
    /// they never commit more than it (0: no limit). Unset: the machine's
    /// physical memory, at most kDefaultWorkerMemory per worker. Not applied
    /// under AddressSanitizer, which reserves terabytes of address space.
    std::optional<uint64_t> memory_budget;
};

/// The largest share of the default budget one worker gets (each worker's
/// limit before the budget was the run's): a runaway allocation stops there
/// even on a machine with more memory.
constexpr uint64_t kDefaultWorkerMemory = uint64_t{8} << 30;

/// The machine's physical memory in bytes (0 if unknown).
uint64_t physical_memory();

/// The run's memory budget: `isolation.memory_budget`, or by default the
/// machine's physical memory, at most kDefaultWorkerMemory for each of the
/// `workers` that run at once (0: no limit).
uint64_t run_memory_budget(const Isolation& isolation, unsigned workers);

/// The address space each of `workers` workers that run at once may use: an
/// equal share of `budget` (0: no limit).
uint64_t worker_memory_limit(uint64_t budget, unsigned workers);

/// Runs one job in this process; an exception from the check becomes an Error
/// result. `memory_note` follows an out-of-memory message (what the limit was).
CheckResult run_job_here(const Job& job, const CheckContext& ctx, const std::string& memory_note = {});

/// Runs the jobs in worker processes, `threads` CPU threads in all, and returns
/// their results in job order. `over_budget` counts the workers killed for
/// their time budget.
std::vector<CheckResult> run_jobs_isolated(const std::vector<Job>& jobs, const RunOptions& options,
                                           const Isolation& isolation, unsigned threads,
                                           const ProgressCallback& progress, int& over_budget);

}  // namespace warpcheck
