// Runs of one case through the recording and replaying cases
// (validate/samples/replay_case.h): the jobs the selection gives the case, run
// on its wrapper under the case's own name, so that every stream, and so every
// input asked, is the one the case itself gets.
#pragma once

#include <vector>

#include "reports/progress_callback.h"
#include "reports/result.h"
#include "validate/run/job.h"
#include "validate/run/worker.h"
#include "validate/samples/replay_case.h"

namespace warpcheck {

/// The jobs of `jobs` that concern `original`, for `wrapper` instead: each
/// check's applicability decided again (a replayed case has no inverse, so the
/// round trips become n/a rows).
std::vector<Job> jobs_for(const std::vector<Job>& jobs, const WarpCase& original, const WarpCase& wrapper);

/// What a recording run gives: the run itself (the warp's own results), and the
/// distinct inputs its checks asked, sorted, with the warp's outputs for them
/// (and the value sample returned with each, where it returns one).
struct Recording {
    RunResult run;
    RecordedSamples samples;
};

/// Runs the jobs of `warp` in this process (a worker process's record would
/// be lost with it) and records every input.
Recording record_run(const WarpCase& warp, const std::vector<Job>& jobs, const RunOptions& options,
                     const ProgressCallback& progress = {});

/// Runs the jobs of `reference` with its outputs replayed from `table`.
RunResult replay_run(const WarpCase& reference, RecordedSamples table, const std::vector<Job>& jobs,
                     const RunOptions& options, const Isolation& isolation = {}, const ProgressCallback& progress = {});

/// Whether sample returns a value with its point that a table carries as an
/// extra column (a pdf, a weight, a remapped u).
bool returns_value(const WarpCase& warp);

}  // namespace warpcheck
