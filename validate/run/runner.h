// The runner: runs (case, check) jobs across a thread pool, seeds each job's
// stream from its names and the global seed, and applies the multiple-test
// correction to every statistical result.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "validate/checks/check.h"
#include "validate/api/registry.h"
#include "reports/progress_callback.h"
#include "reports/result.h"
#include "validate/run/job.h"
#include "validate/run/worker.h"

namespace warpcheck {

/// The stream of one (case, check) job: a function of the names and the seed only.
StreamId job_stream(const WarpCase& warp, const Check& check, uint64_t seed);

/// Whether `check` is for cases of `warp`'s kind: the BSDF checks
/// (Check::about_bsdfs) take BSDF cases only, and the others every other case.
/// select_jobs and the GoogleTest assertions pair cases and checks by it.
bool check_is_for(const Check& check, const WarpCase& warp);

/// The jobs of a selection, in registry order (case by case, then check by check).
/// Empty `case_patterns` selects every case; empty `check_names` every check that
/// runs by default. Cases marked as known flaws (and checks of a case marked as
/// a known flaw) are left out unless options.include_flawed is set or a pattern
/// is the case's full name. A check that does not apply for want of a part of
/// the case gives a job that only carries the reason.
std::vector<Job> select_jobs(const Registry& registry, const std::vector<std::string>& case_patterns,
                             const std::vector<std::string>& check_names, const RunOptions& options);

/// Part i of n of a run (1 <= index <= count): the jobs whose position in the
/// whole run's job list is index - 1 modulo count. Round robin, so that the
/// checks of one case, which differ in cost, spread over the shards.
struct Shard {
    unsigned index = 1;
    unsigned count = 1;
};

/// The one command that reruns a row: `program` (quoted where the shell
/// would not take it as it is) --filter '<case>' --check <check> --seed S
/// --samples N, and --max-float-bias R where R > 0. Every rerun line comes
/// from here (a merge rebuilds its rows' from their names and settings
/// instead of printing what a shard file says).
std::string rerun_command(const std::string& program, const std::string& case_name, const std::string& check_name,
                          uint64_t seed, uint64_t samples, double max_float_bias);

/// Reads "I/N" (1 <= I <= N <= 1000000), or returns nullopt.
std::optional<Shard> parse_shard(std::string_view spec);

/// The jobs of one shard, in the order of the whole run.
std::vector<Job> shard_jobs(const std::vector<Job>& jobs, Shard shard);

/// The statistical tests among the jobs (Check::statistical): the family the
/// Šidák correction of a run of these jobs covers.
int statistical_tests(const std::vector<Job>& jobs);

/// The machine a run's timings come from, as its result records it
/// (RunInfo::machine): kernel, processor architecture, hardware threads and
/// the vector path of the chi-square lanes (AVX-512, AVX2 or scalar), which
/// sets the speed of the chi2 rows.
std::string machine_description();

/// Runs the jobs and returns their results in job order. Exceptions from a check
/// become Error results; the run goes on. With isolation, so do crashes, exits,
/// runaway allocation and checks over their CPU time budget (validate/run/worker.h);
/// without, a check over its budget is asked to stop and waited for. Statistical
/// results get their verdict from the Šidák-corrected level over all results
/// that carry a p-value. The figures are the same either way.
RunResult run_jobs(const std::vector<Job>& jobs, const RunOptions& options, const ProgressCallback& progress = {},
                   const Isolation& isolation = {});

/// Applies the Šidák-corrected level (chi2/multiple_testing.h) for a family of
/// `family_tests` tests (unset: the results with a p-value) to every result
/// with a p-value: a p-value below the level, or NaN, fails.
void apply_multiple_test_correction(RunResult& run, double family_alpha,
                                    std::optional<int> family_tests = std::nullopt);

}  // namespace warpcheck
