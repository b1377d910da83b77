// `validate --merge`: the shards of one run (validate --shard I/N --json FILE)
// combined into the run they are parts of.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "reports/result.h"

namespace warpcheck {

struct MergeError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// One shard's results and the file they came from (for the messages).
struct ShardFile {
    std::string path;
    RunResult run;
};

/// The whole run: the results in the order of the unsharded run (shard I holds
/// the jobs I-1, I-1+N, ... of it), with the settings the shards share. Throws
/// MergeError naming the file when the shards are not the parts of one run:
/// a file that is not a shard, different seeds, sample counts, alpha, tool
/// versions, shard counts or selections, a shard given twice or missing, a
/// (case, check) in two shards.
RunResult merge_shards(const std::vector<ShardFile>& shards);

}  // namespace warpcheck
