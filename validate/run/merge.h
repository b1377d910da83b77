// `validate --merge`: the shards of one run (validate --shard I/N --json FILE)
// checked and combined into the run they are parts of.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "reports/result.h"

namespace warpcheck {

struct MergeError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A shard file larger than this is refused before it is read: 28 times the
/// 9 MB JSON of `validate --all`. Merging takes about 5 times a shard's size in
/// memory at the peak (the text, the parsed document, the results: 53 MB for
/// that 9 MB shard, measured), so a shard at the limit needs about 1.3 GB.
inline constexpr uint64_t kMaxShardFileBytes = uint64_t{256} << 20;

/// One shard's results, the totals its file states, and the file they came
/// from (for the messages).
struct ShardFile {
    std::string path;
    RunResult run;
    Totals stated_totals;
};

/// The shard in the JSON file at `path`. Reads only a regular file (a FIFO,
/// a device or a folder is refused without being read) of at most
/// kMaxShardFileBytes. Throws MergeError naming the file.
ShardFile read_shard_file(const std::string& path);

/// The whole run: the results in the order of the unsharded run (shard I holds
/// the jobs I-1, I-1+N, ... of it), with the settings the shards share.
///
/// Each shard is checked before it is used, and any disagreement throws
/// MergeError naming the file and, where there is one, the row:
/// - it is a shard with a digest of its run (validate/run/run_digest.h), and the
///   shards share it and every setting it covers: shards of different
///   selections or settings are refused, even with the same number of jobs;
/// - each row matches its own digest (an edited verdict, figure or name);
/// - its verdicts follow from its own figures: the per-test level is the Sidak
///   level of the run's alpha over its statistical tests, every p-value is
///   judged at it, and no row that says pass has a p-value below it (or NaN);
/// - its stated totals count its rows;
/// - the shards are all there, each once, with the number of rows the run's
///   job count gives it, no (case, check) in two of them, and the whole job
///   list and settings give their digest.
/// Each row's rerun command is made again from its case, check and the run's
/// settings (runner.h, rerun_command), with the program the shard's command
/// names where it reads as one (a plain or single-quoted word), else
/// `program`: a command in a shard file is never printed as it is given.
RunResult merge_shards(const std::vector<ShardFile>& shards, const std::string& program = "validate");

/// The shards of the run that `shards` are parts of and that are not among
/// them, as "I/N", in order (none when all are there): after a partial run on
/// a cluster, the ones to run again. The shards given are checked as
/// merge_shards checks them (MergeError).
std::vector<std::string> missing_shards(const std::vector<ShardFile>& shards);

/// A warning for a shard whose JSON results take `json_bytes`: empty when
/// they fit the kMaxShardFileBytes that --merge reads, else what to do (more
/// shards). `shard_count` is the run's.
std::string shard_size_warning(uint64_t json_bytes, unsigned shard_count);

}  // namespace warpcheck
