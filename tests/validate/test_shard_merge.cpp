// --shard I/N and --merge: four shards merged are the unsharded run, figure for
// figure and verdict for verdict; shards of different runs are refused.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/run_command.h"

namespace warpcheck {
namespace {

namespace fs = std::filesystem;
using testing::run_validate;

// alpha 0.5 makes some chi-square rows fail at the corrected level (about 0.05
// over this selection's tests), so verdicts that hang on the whole run's level
// are compared too.
constexpr const char* kSelection = "--filter cone --filter linear --alpha 0.5 --color never --progress none ";
constexpr const char* kSamples = "--samples 20000";

std::string fmt_shard(int i) { return "shard" + std::to_string(i) + ".json"; }

struct ShardRuns {
    fs::path dir = fs::temp_directory_path() / ("warpcheck-shards-" + std::to_string(::getpid()));
    ShardRuns() {
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~ShardRuns() {
        std::error_code ignored;
        fs::remove_all(dir, ignored);
    }
    std::string operator/(const std::string& name) const { return (dir / name).string(); }
    /// Runs shard i of n with extra arguments, writing shard<i>.json.
    testing::CommandResult shard(int i, int n, const std::string& extra = kSamples) const {
        return run_validate(std::string(kSelection) + extra + " --shard " + std::to_string(i) + "/" +
                            std::to_string(n) + " --json " + (dir / fmt_shard(i)).string());
    }
    std::string shard_files(int n) const {
        std::string files;
        for (int i = 1; i <= n; ++i) files.append(" ").append((dir / fmt_shard(i)).string());
        return files;
    }
};

nlohmann::json read_json(const std::string& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

/// The table without the summary line's wall time.
std::string table_rows(const std::string& output) {
    // The table without its wall time and the lines that name the files written.
    const std::string rows = std::regex_replace(output, std::regex(" in [0-9.]+ s "), " in (time) s ");
    return std::regex_replace(rows, std::regex("[^\n]* written to [^\n]*\n"), "");
}

TEST(ShardMerge, FourShardsMergedAreTheUnshardedRun) {
    ShardRuns runs;
    const auto whole = run_validate(std::string(kSelection) + kSamples + " --json " + runs / "whole.json");
    ASSERT_NE(whole.status, 2) << whole.output;
    for (int i = 1; i <= 4; ++i) ASSERT_NE(runs.shard(i, 4).status, 2);
    const auto merged = run_validate("--color never --merge" + runs.shard_files(4) + " --json " +
                                     runs / "merged.json" + " --junit " + runs / "merged.xml");
    EXPECT_EQ(merged.status, whole.status) << merged.output;
    EXPECT_EQ(table_rows(merged.output), table_rows(whole.output));

    nlohmann::json a = read_json(runs / "whole.json"), b = read_json(runs / "merged.json");
    ASSERT_GT(a["results"].size(), 20u);
    int failed = 0;
    for (auto* document : {&a, &b})
        for (auto& r : (*document)["results"]) {
            r.erase("seconds");  // timings differ from run to run
            r.erase("phases");
        }
    for (const auto& r : a["results"]) failed += r["verdict"] == "fail";
    EXPECT_GT(failed, 0) << "the selection should have rows that fail at alpha 0.5";
    EXPECT_EQ(a["results"], b["results"]);
    for (const char* key : {"seed", "samples", "family_alpha", "per_test_alpha", "statistical_tests"})
        EXPECT_EQ(a["run"][key], b["run"][key]) << key;
    EXPECT_EQ(a["totals"], b["totals"]);
    std::ifstream junit(runs / "merged.xml");
    std::stringstream text;
    text << junit.rdbuf();
    EXPECT_NE(text.str().find("<testcase"), std::string::npos);
}

TEST(ShardMerge, AShardIsJudgedAtTheWholeRunsLevel) {
    ShardRuns runs;
    const auto whole = run_validate(std::string(kSelection) + kSamples + " --json " + runs / "whole.json");
    runs.shard(2, 3);
    const auto a = read_json(runs / "whole.json"), b = read_json(runs / "shard2.json");
    EXPECT_EQ(a["run"]["per_test_alpha"], b["run"]["per_test_alpha"]);
    EXPECT_EQ(a["run"]["statistical_tests"], b["run"]["statistical_tests"]);
    EXPECT_EQ(b["run"]["shard"]["index"], 2);
    EXPECT_EQ(b["run"]["shard"]["jobs"], a["results"].size());
}

TEST(ShardMerge, InvalidShardSpecsExitTwo) {
    for (const char* spec : {"0/4", "5/4", "1/0", "a/b", "2", "1/4x", "-1/4", "''"}) {
        const auto r = run_validate(std::string("--filter cone --shard ") + spec);
        EXPECT_EQ(r.status, 2) << spec << "\n" << r.output;
        EXPECT_NE(r.output.find("--shard"), std::string::npos) << r.output;
    }
}

TEST(ShardMerge, ShardsOfDifferentRunsAreRefused) {
    ShardRuns runs;
    for (int i = 1; i <= 3; ++i) ASSERT_NE(runs.shard(i, 3).status, 2);
    const std::string three = runs.shard_files(3);
    const std::string s1 = runs / "shard1.json", s2 = runs / "shard2.json", s3 = runs / "shard3.json";
    const auto expect_refused = [&](const std::string& files, const std::string& why) {
        const auto r = run_validate("--merge " + files);
        EXPECT_EQ(r.status, 2) << files << "\n" << r.output;
        EXPECT_NE(r.output.find(why), std::string::npos) << r.output;
    };
    expect_refused(s1 + " " + s2, "shards missing: 3/3");
    expect_refused(three + " " + s1, "shard 1/3 is given twice");
    // One shard of another seed, another sample count, another tool version.
    runs.shard(3, 3, std::string(kSamples) + " --seed 7");
    expect_refused(three, "their seed differs");
    runs.shard(3, 3, "--samples 30000");
    expect_refused(three, "their sample count differs");
    runs.shard(3, 3);
    std::string text;
    {
        std::ifstream in(s3);
        std::stringstream buffer;
        buffer << in.rdbuf();
        text = std::regex_replace(buffer.str(), std::regex("\"version\":\"[^\"]*\""), "\"version\":\"0.0.1\"");
    }
    std::ofstream(s3) << text;
    expect_refused(three, "their tool version differs");
    // A whole run, a missing file, a file that is not JSON.
    run_validate(std::string(kSelection) + kSamples + " --json " + runs / "whole.json");
    expect_refused(runs / "whole.json", "not a shard");
    expect_refused(runs / "nothing.json", "cannot be read");
    std::ofstream(runs / "broken.json") << "{\"results\": [";
    expect_refused(runs / "broken.json", "not a JSON document");
}

}  // namespace
}  // namespace warpcheck
