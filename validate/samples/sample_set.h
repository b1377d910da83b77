// Samples from elsewhere judged as results: a set of independent draws against
// a case's density, and the rows of comparisons gathered into a run with the
// same result model, multiple-test correction, JSON and HTML as any other.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "chi2/parallel.h"
#include "reports/result.h"
#include "validate/api/warp_case.h"
#include "validate/checks/check.h"

namespace warpcheck {

/// The one-sample checks that need neither the inputs nor an inverse, on
/// samples drawn elsewhere (with their own random numbers) and judged against
/// `reference`'s pdf and domain:
///   - "samples_consistency": every sample lies in the domain with a finite,
///     positive pdf (a zero pdf exactly on the boundary is counted, not failed);
///     unlike "consistency", which can probe the warp, it grants no allowance
///     for samples rounded across the edge of a smaller support;
///   - "samples_chi2": Pearson's test against the pdf integrated over the
///     cells, as "chi2" runs it (chi2::run_chi2_test), the rows of the samples
///     taken in order as its chunks.
/// Rows are named after the reference case.
std::vector<CheckResult> judge_sample_set(const WarpCase& reference, std::span<const WarpOutput> samples,
                                          const RunOptions& options, const chi2::ParallelFor& parallel = chi2::serial_for);

/// A run of rows made without the runner: settings and environment filled in
/// as run_jobs does, each row's rerun command set to `command`, and the
/// Sidak-corrected level applied over the rows with a p-value.
RunResult run_of_rows(std::vector<CheckResult> rows, const RunOptions& options, const std::string& command);

}  // namespace warpcheck
