#include "validate/run/run_digest.h"

#include <algorithm>
#include <bit>
#include <cstdint>

#include <fmt/format.h>

#include "reports/result_json.h"
#include "sampling/hash.h"

namespace warpcheck {
namespace {

std::string hex(uint64_t h) { return fmt::format("{:016x}", h); }

/// `text` as the JSON report holds it, and as the merge reads it back: each
/// byte that is not valid UTF-8 replaced by U+FFFD (render_json's error
/// handler). The digest hashes these bytes, so that a shard with such a case
/// name merges; a valid name is its own bytes, and its digest unchanged.
std::string as_json_holds(const std::string& text) {
    const std::string quoted = ResultJson(text).dump(-1, ' ', false, ResultJson::error_handler_t::replace);
    return ResultJson::parse(quoted).get<std::string>();
}

}  // namespace

std::string run_digest(const RunInfo& info, const std::vector<JobName>& whole_run) {
    uint64_t h = hash_values(hash_string("warpcheck run digest 1"), hash_string(info.tool_version), info.seed,
                             info.samples, std::bit_cast<uint64_t>(info.family_alpha), info.strict ? 1 : 0,
                             std::bit_cast<uint64_t>(info.max_float_bias), info.statistical_tests, whole_run.size());
    for (const JobName& job : whole_run)
        h = hash_combine(hash_combine(h, hash_string(as_json_holds(job.case_name))),
                         hash_string(as_json_holds(job.check_name)));
    return hex(h);
}

std::string row_digest(const CheckResult& row, const std::string& run_digest) {
    // The row as the JSON report writes it (so that a row read back from a
    // report has the digest it was written with), without its timings, and
    // with its figures in the order of their names: they are the members of a
    // JSON object, whose order a program that rewrites the file need not keep.
    CheckResult timeless = row;
    timeless.seconds = 0.0;
    timeless.phases.clear();
    timeless.digest.clear();
    std::stable_sort(timeless.figures.begin(), timeless.figures.end(),
                     [](const Figure& a, const Figure& b) { return a.name < b.name; });
    const std::string text = FieldWriter<TextNumbers>::write(timeless).dump(-1, ' ', false,
                                                                            ResultJson::error_handler_t::replace);
    return hex(hash_combine(hash_string(run_digest), hash_string(text)));
}

void seal_run(RunResult& run, const std::vector<JobName>& whole_run) {
    run.info.digest = run_digest(run.info, whole_run);
    for (CheckResult& row : run.results) row.digest = row_digest(row, run.info.digest);
}

}  // namespace warpcheck
