// Isolated jobs: each (case, check) job runs in a forked worker process, so a
// warp that crashes, aborts, calls exit(), spins forever or allocates without
// bound costs one ERROR row instead of the run. The parent stays single-threaded
// (it forks, so it must): it only hands out jobs, reads results back over pipes
// (validate/result_codec.h) and watches the children's time.
#pragma once

#include <cstdint>
#include <vector>

#include "reports/progress_callback.h"
#include "reports/result.h"
#include "validate/check.h"

namespace warpcheck {

struct Job;

/// How the runner keeps warps apart from the run.
struct Isolation {
    /// Run each job in a worker process. Off: jobs run on threads of this
    /// process (for debuggers), where a budget can only ask a check to stop.
    bool enabled = false;
    /// RLIMIT_AS of each worker in bytes (0: none). Not applied under
    /// AddressSanitizer, which reserves terabytes of address space.
    uint64_t memory_limit = uint64_t{8} << 30;
};

/// Runs one job in this process; an exception from the check becomes an Error result.
CheckResult run_job_here(const Job& job, const CheckContext& ctx);

/// Runs the jobs in worker processes, `threads` CPU threads in all, and returns
/// their results in job order. `over_budget` counts the workers killed for
/// their time budget.
std::vector<CheckResult> run_jobs_isolated(const std::vector<Job>& jobs, const RunOptions& options,
                                           const Isolation& isolation, unsigned threads,
                                           const ProgressCallback& progress, int& over_budget);

}  // namespace warpcheck
