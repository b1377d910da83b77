#include "validate/merge.h"

#include <algorithm>
#include <set>
#include <utility>

#include <fmt/format.h>

namespace warpcheck {
namespace {

/// What every shard of one run shares, beside the shard count.
bool same_run(const RunInfo& a, const RunInfo& b, std::string& what) {
    const auto differ = [&](bool d, const char* name) {
        if (d && what.empty()) what = name;
        return d;
    };
    differ(a.tool_version != b.tool_version, "tool version");
    differ(a.seed != b.seed, "seed");
    differ(a.samples != b.samples, "sample count");
    differ(!(a.family_alpha == b.family_alpha), "alpha");
    differ(a.shard_count != b.shard_count, "shard count");
    differ(a.run_jobs != b.run_jobs || a.statistical_tests != b.statistical_tests, "selection of cases and checks");
    return what.empty();
}

/// How many of the whole run's jobs shard `index` of `count` holds.
uint64_t jobs_in_shard(uint64_t jobs, unsigned index, unsigned count) { return (jobs + count - index) / count; }

void check_shards(const std::vector<ShardFile>& shards) {
    if (shards.empty()) throw MergeError("no shard files given");
    const RunInfo& first = shards.front().run.info;
    std::set<unsigned> seen;
    for (const ShardFile& s : shards) {
        const RunInfo& info = s.run.info;
        if (info.shard_count == 0)
            throw MergeError(fmt::format("{}: not a shard (written by a run without --shard)", s.path));
        std::string what;
        if (!same_run(first, info, what))
            throw MergeError(fmt::format("{} and {} are shards of different runs: their {} differs", shards[0].path,
                                         s.path, what));
        if (!seen.insert(info.shard_index).second)
            throw MergeError(fmt::format("{}: shard {}/{} is given twice", s.path, info.shard_index, info.shard_count));
        if (s.run.results.size() != jobs_in_shard(info.run_jobs, info.shard_index, info.shard_count))
            throw MergeError(fmt::format("{}: shard {}/{} of {} jobs holds {} results, not {}", s.path,
                                         info.shard_index, info.shard_count, info.run_jobs, s.run.results.size(),
                                         jobs_in_shard(info.run_jobs, info.shard_index, info.shard_count)));
    }
    std::string missing;
    for (unsigned i = 1; i <= first.shard_count; ++i)
        if (!seen.count(i)) missing += fmt::format("{}{}/{}", missing.empty() ? "" : ", ", i, first.shard_count);
    if (!missing.empty()) throw MergeError("shards missing: " + missing);
}

}  // namespace

RunResult merge_shards(const std::vector<ShardFile>& shards) {
    check_shards(shards);
    RunResult merged;
    merged.info = shards.front().run.info;
    const unsigned count = merged.info.shard_count;
    std::vector<const RunResult*> by_index(count);
    for (const ShardFile& s : shards) {
        by_index[s.run.info.shard_index - 1] = &s.run;
        merged.info.threads = std::max(merged.info.threads, s.run.info.threads);
        merged.info.wall_seconds = std::max(merged.info.wall_seconds, s.run.info.wall_seconds);
        merged.info.started_at = std::min(merged.info.started_at, s.run.info.started_at);
        merged.info.abandoned_checks += s.run.info.abandoned_checks;
    }
    merged.info.abandoned_checks -= shards.front().run.info.abandoned_checks;
    std::set<std::pair<std::string, std::string>> jobs;
    for (uint64_t j = 0; j < merged.info.run_jobs; ++j) {
        const CheckResult& r = by_index[j % count]->results[j / count];
        if (!jobs.insert({r.case_name, r.check_name}).second)
            throw MergeError(fmt::format("{} on {} is in more than one shard", r.check_name, r.case_name));
        merged.results.push_back(r);
    }
    merged.info.shard_index = merged.info.shard_count = 0;
    return merged;
}

}  // namespace warpcheck
