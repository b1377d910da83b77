#include "validate/run/merge.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <set>
#include <utility>

#include <fmt/format.h>

#include "chi2/multiple_testing.h"
#include "reports/json_input.h"
#include "validate/run/run_digest.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

/// Closes a file descriptor on the way out.
struct FileDescriptor {
    int fd;
    ~FileDescriptor() {
        if (fd >= 0) ::close(fd);
    }
};

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
    throw MergeError(fmt::format("{}: {}", path, why));
}

/// The contents of a regular file of at most kMaxShardFileBytes. Opened
/// without blocking, so that a FIFO without a writer is refused, not waited on.
std::string read_bounded(const std::string& path) {
    const FileDescriptor file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC)};
    if (file.fd < 0) refuse(path, fmt::format("cannot be read: {}", std::strerror(errno)));
    struct stat st {};
    if (::fstat(file.fd, &st) != 0) refuse(path, fmt::format("cannot be read: {}", std::strerror(errno)));
    if (S_ISDIR(st.st_mode)) refuse(path, "cannot be read: it is a folder");
    if (!S_ISREG(st.st_mode)) refuse(path, "cannot be read: not a regular file (a FIFO, device or socket)");
    const auto too_large = [&](uint64_t size) {
        refuse(path, fmt::format("cannot be read: {} bytes is over the limit of {} MiB for a shard", size,
                                 kMaxShardFileBytes >> 20));
    };
    if (static_cast<uint64_t>(st.st_size) > kMaxShardFileBytes) too_large(static_cast<uint64_t>(st.st_size));
    std::string text(static_cast<std::size_t>(st.st_size) + 1, '\0');  // one more: a file that grew shows it
    std::size_t size = 0;
    for (;;) {
        if (size == text.size()) {
            if (size > kMaxShardFileBytes) too_large(size);
            text.resize(std::min<std::size_t>(2 * size, kMaxShardFileBytes + 1));
        }
        const ssize_t got = ::read(file.fd, text.data() + size, text.size() - size);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) refuse(path, fmt::format("cannot be read: {}", std::strerror(errno)));
        if (got == 0) break;
        size += static_cast<std::size_t>(got);
    }
    text.resize(size);
    return text;
}

std::string describe(const Totals& t) {
    return fmt::format("{} checks, {} passed, {} failed, {} errors, {} not applicable", t.checks, t.passed, t.failed,
                       t.errors, t.not_applicable);
}

std::string row_name(const ShardFile& shard, std::size_t i) {
    const CheckResult& r = shard.run.results[i];
    return fmt::format("{}: row {} ({} on {})", shard.path, i + 1, r.check_name, r.case_name);
}

/// A row's verdict against its own p-value, by the runner's rule
/// (apply_multiple_test_correction): every p-value is judged at the run's
/// per-test level, and a pass needs p >= level (a NaN p-value fails). A row
/// may fail with a p-value above the level (for another reason), never pass below it.
void check_verdict(const ShardFile& shard, std::size_t i) {
    const CheckResult& r = shard.run.results[i];
    const double level = shard.run.info.per_test_alpha;
    if (!r.p_value) {
        if (r.level) throw MergeError(row_name(shard, i) + " has a level but no p-value");
        return;
    }
    if (!r.level || !(*r.level == level))
        throw MergeError(fmt::format("{}: its level {} is not the run's per-test level {}", row_name(shard, i),
                                     r.level ? fmt::format("{}", *r.level) : "(none)", level));
    if (r.verdict == Verdict::Pass && !(*r.p_value >= level))
        throw MergeError(fmt::format("{} says pass, but its p-value {} is below the per-test level {}",
                                     row_name(shard, i), *r.p_value, level));
}

/// What one shard says about itself holds: see merge_shards.
void check_shard_itself(const ShardFile& shard) {
    const RunInfo& info = shard.run.info;
    if (info.shard_count == 0) refuse(shard.path, "not a shard (written by a run without --shard)");
    if (info.digest.empty()) refuse(shard.path, "has no digest of its run (not written by this warpcheck's validate)");
    const double level = chi2::sidak_level(info.family_alpha, info.statistical_tests);
    if (!(info.per_test_alpha == level))
        refuse(shard.path, fmt::format("its per-test level {} is not {}, the Sidak level of alpha {} over {} tests",
                                       info.per_test_alpha, level, info.family_alpha, info.statistical_tests));
    for (std::size_t i = 0; i < shard.run.results.size(); ++i) {
        check_verdict(shard, i);
        if (shard.run.results[i].digest != row_digest(shard.run.results[i], info.digest))
            throw MergeError(row_name(shard, i) + " does not match its digest: it was changed after the run");
    }
    if (!(shard.stated_totals == shard.run.totals()))
        refuse(shard.path, fmt::format("its totals ({}) do not count its rows ({})", describe(shard.stated_totals),
                                       describe(shard.run.totals())));
}

/// What every shard of one run shares, beside the shard count.
bool same_run(const RunInfo& a, const RunInfo& b, std::string& what) {
    const auto differ = [&](bool d, const char* name) {
        if (d && what.empty()) what = name;
    };
    differ(a.tool_version != b.tool_version, "tool version");
    differ(a.seed != b.seed, "seed");
    differ(a.samples != b.samples, "sample count");
    differ(!(a.family_alpha == b.family_alpha), "alpha");
    differ(a.strict != b.strict, "--strict setting");
    differ(!(a.max_float_bias == b.max_float_bias), "--max-float-bias");
    differ(a.shard_count != b.shard_count, "shard count");
    differ(a.run_jobs != b.run_jobs || a.statistical_tests != b.statistical_tests || a.digest != b.digest,
           "selection of cases and checks (their digests differ)");
    return what.empty();
}

/// How many of the whole run's jobs shard `index` of `count` holds.
uint64_t jobs_in_shard(uint64_t jobs, unsigned index, unsigned count) { return (jobs + count - index) / count; }

/// Checks each shard and that they are parts of one run, each once; returns
/// the indices they hold.
std::set<unsigned> check_present_shards(const std::vector<ShardFile>& shards) {
    if (shards.empty()) throw MergeError("no shard files given");
    const RunInfo& first = shards.front().run.info;
    std::set<unsigned> seen;
    for (const ShardFile& s : shards) {
        check_shard_itself(s);
        const RunInfo& info = s.run.info;
        std::string what;
        if (!same_run(first, info, what))
            throw MergeError(fmt::format("{} and {} are shards of different runs: their {} differs", shards[0].path,
                                         s.path, what));
        if (!seen.insert(info.shard_index).second)
            refuse(s.path, fmt::format("shard {}/{} is given twice", info.shard_index, info.shard_count));
        if (s.run.results.size() != jobs_in_shard(info.run_jobs, info.shard_index, info.shard_count))
            refuse(s.path, fmt::format("shard {}/{} of {} jobs holds {} results, not {}", info.shard_index,
                                       info.shard_count, info.run_jobs, s.run.results.size(),
                                       jobs_in_shard(info.run_jobs, info.shard_index, info.shard_count)));
    }
    return seen;
}

void check_shards(const std::vector<ShardFile>& shards) {
    std::string missing;
    for (const std::string& shard : missing_shards(shards)) missing += (missing.empty() ? "" : ", ") + shard;
    if (!missing.empty())
        throw MergeError("shards missing: " + missing + " (run them, or list them with --missing-shards)");
}

/// The merged run's rows in the unsharded order, each (case, check) once.
std::vector<CheckResult> interleave(const std::vector<ShardFile>& shards, uint64_t jobs, unsigned count) {
    std::vector<const RunResult*> by_index(count);
    for (const ShardFile& s : shards) by_index[s.run.info.shard_index - 1] = &s.run;
    std::vector<CheckResult> rows;
    std::set<std::pair<std::string, std::string>> seen;
    for (uint64_t j = 0; j < jobs; ++j) {
        const CheckResult& r = by_index[j % count]->results[j / count];
        if (!seen.insert({r.case_name, r.check_name}).second)
            throw MergeError(fmt::format("{} on {} is in more than one shard", r.check_name, r.case_name));
        rows.push_back(r);
    }
    return rows;
}

/// The program a shard's rerun command names, where it reads as rerun_command
/// writes one (a plain word, or one in single quotes, before " --filter "):
/// the shard's program reruns its rows. Otherwise `fallback`, the merging
/// program. Only the program is taken: the rest is made again.
std::string rerun_program(const std::string& command, const std::string& fallback) {
    const std::size_t end = command.find(" --filter ");
    if (end == std::string::npos || end == 0) return fallback;
    const std::string word = command.substr(0, end);
    if (word.size() >= 2 && word.front() == '\'' && word.back() == '\'') {
        const std::string inner = word.substr(1, word.size() - 2);
        return inner.empty() || inner.find('\'') != std::string::npos ? fallback : inner;
    }
    const bool plain = word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+./:=@%,") ==
                       std::string::npos;
    return plain ? word : fallback;
}

/// A shard has the legends of its own rows' checks; the merged run has each
/// check's once, in the order its rows first appear, as the unsharded run has.
std::vector<CheckLegend> merged_legends(const std::vector<ShardFile>& shards, const std::vector<CheckResult>& rows) {
    std::vector<CheckLegend> out;
    for (const CheckResult& r : rows) {
        if (std::any_of(out.begin(), out.end(), [&](const CheckLegend& l) { return l.check == r.check_name; }))
            continue;
        for (const ShardFile& s : shards) {
            const auto& from = s.run.info.legends;
            const auto it = std::find_if(from.begin(), from.end(), [&](const CheckLegend& l) { return l.check == r.check_name; });
            if (it == from.end()) continue;
            out.push_back(*it);
            break;
        }
    }
    return out;
}

}  // namespace

std::vector<std::string> missing_shards(const std::vector<ShardFile>& shards) {
    const std::set<unsigned> seen = check_present_shards(shards);
    const unsigned count = shards.front().run.info.shard_count;
    std::vector<std::string> missing;
    for (unsigned i = 1; i <= count; ++i)
        if (!seen.count(i)) missing.push_back(fmt::format("{}/{}", i, count));
    return missing;
}

ShardFile read_shard_file(const std::string& path) {
    const std::string text = read_bounded(path);
    try {
        JsonResults document = read_json_results(text);
        return {path, std::move(document.run), document.totals};
    } catch (const JsonInputError& e) {
        refuse(path, e.what());
    }
}

RunResult merge_shards(const std::vector<ShardFile>& shards, const std::string& program) {
    check_shards(shards);
    RunResult merged;
    merged.info = shards.front().run.info;
    merged.info.abandoned_checks = 0;
    for (const ShardFile& s : shards) {
        merged.info.threads = std::max(merged.info.threads, s.run.info.threads);
        merged.info.wall_seconds = std::max(merged.info.wall_seconds, s.run.info.wall_seconds);
        merged.info.started_at = std::min(merged.info.started_at, s.run.info.started_at);
        merged.info.abandoned_checks += s.run.info.abandoned_checks;
    }
    merged.results = interleave(shards, merged.info.run_jobs, merged.info.shard_count);
    merged.info.legends = merged_legends(shards, merged.results);
    std::vector<JobName> jobs;
    for (const CheckResult& r : merged.results) jobs.push_back({r.case_name, r.check_name});
    if (run_digest(merged.info, jobs) != merged.info.digest)
        refuse(shards.front().path, fmt::format("the shards' digest {} is not that of their settings and (case, check) "
                                                "list ({}): a setting or a name was changed after the run",
                                                merged.info.digest, run_digest(merged.info, jobs)));
    merged.info.shard_index = merged.info.shard_count = 0;
    for (CheckResult& r : merged.results) {
        r.rerun_command = rerun_command(rerun_program(r.rerun_command, program), r.case_name, r.check_name,
                                        merged.info.seed, merged.info.samples, merged.info.max_float_bias);
        r.digest = row_digest(r, merged.info.digest);
    }
    return merged;
}

std::string shard_size_warning(uint64_t json_bytes, unsigned shard_count) {
    if (json_bytes <= kMaxShardFileBytes) return {};
    const uint64_t mib = uint64_t{1} << 20;
    const uint64_t needed = (json_bytes * shard_count + kMaxShardFileBytes - 1) / kMaxShardFileBytes;
    return fmt::format("this shard's JSON results are {} MiB, over the {} MiB that --merge reads: run the selection "
                       "in at least {} shards (--shard I/{})",
                       (json_bytes + mib - 1) / mib, kMaxShardFileBytes >> 20, needed, needed);
}

}  // namespace warpcheck
