// Digests that let `validate --merge` check its shards (validate/run/merge.h). A
// run's digest covers what decides its figures and verdicts: the tool version,
// seed, sample count, family alpha, --strict, --max-float-bias, the number of
// statistical tests and the whole run's (case, check) list in order (each name
// as the JSON report holds it: invalid UTF-8 as U+FFFD), all shards
// together; so every shard of one run has the same digest and shards of
// different selections or settings differ. A row's digest covers the row, all
// but its timings (seconds, phases: they differ from run to run), with its
// figures in the order of their names (a JSON object's members have no order),
// and its run's digest. Both are 64-bit FNV-1a hashes (sampling/hash.h), written
// as 16 hex digits: they catch accidents and edits, not a forger who recomputes them.
#pragma once

#include <string>
#include <vector>

#include "reports/result.h"

namespace warpcheck {

/// A job of a run as its row names it.
struct JobName {
    std::string case_name;
    std::string check_name;
};

/// The digest of a run with these settings and this whole job list.
std::string run_digest(const RunInfo& info, const std::vector<JobName>& whole_run);

/// The digest of a row of the run whose digest is `run_digest`.
std::string row_digest(const CheckResult& row, const std::string& run_digest);

/// Sets the run's digest and each of its rows': `whole_run` lists the jobs of
/// every shard when `run` is one shard.
void seal_run(RunResult& run, const std::vector<JobName>& whole_run);

}  // namespace warpcheck
