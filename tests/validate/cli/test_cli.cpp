// The validate command: exit statuses and messages for good and bad input.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "support/run_command.h"
#include "support/temp_dir.h"

namespace warpcheck {
namespace {

using testing::run_validate;

TEST(Cli, FilteredRunPassesAndPrintsTheTable) {
    const auto r = run_validate("--filter uniform_cone --samples 20000 --check roundtrip --check consistency");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("uniform_cone[cos_theta_max=0.3]"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("roundtrip"), std::string::npos);
    EXPECT_NE(r.output.find("0 failed, 0 errors"), std::string::npos) << r.output;
}

// --timings: seconds per check and the slowest rows with the parts of their
// compute (the chi-square check times integration, sampling and statistics).
TEST(Cli, TimingsShowWhereTheTimeWent) {
    const auto r = run_validate("--filter 'cosine_hemisphere' --samples 20000 --check chi2 --check roundtrip --timings");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("Where the time went"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("integration "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("sampling+binning "), std::string::npos) << r.output;
    const auto without = run_validate("--filter 'cosine_hemisphere' --samples 20000 --check chi2");
    EXPECT_EQ(without.output.find("Where the time went"), std::string::npos) << without.output;
}

TEST(Cli, ExactCaseNameSelectsOneCase) {
    const auto r = run_validate("--filter 'uniform_cone[cos_theta_max=0.3]' --check roundtrip --samples 10000");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find("cos_theta_max=0.99"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("1 checks: 1 passed"), std::string::npos) << r.output;
}

// --skip-check: every check that would run but the skipped (with --check, the
// named ones but those); an unknown name, or skipping all, is a usage error.
TEST(Cli, SkipCheckRunsTheRestOfTheSelection) {
    const std::string one = "--filter 'uniform_cone[cos_theta_max=0.3]' --samples 10000 --color never ";
    const auto all = run_validate(one);
    const auto skipped = run_validate(one + "--skip-check chi2 --skip-check unbinned");
    EXPECT_EQ(skipped.status, 0) << skipped.output;
    for (const char* check : {" consistency ", " roundtrip ", " tabulated "}) {
        EXPECT_NE(all.output.find(check), std::string::npos) << all.output;
        EXPECT_NE(skipped.output.find(check), std::string::npos) << skipped.output;
    }
    for (const char* check : {" chi2 ", " unbinned "}) {
        EXPECT_NE(all.output.find(check), std::string::npos) << all.output;
        EXPECT_EQ(skipped.output.find(check), std::string::npos) << skipped.output;
    }
    const auto named = run_validate(one + "--check roundtrip --check chi2 --skip-check chi2");
    EXPECT_NE(named.output.find("1 checks: 1 passed"), std::string::npos) << named.output;
    // A check that runs only when asked stays out when another is skipped.
    EXPECT_EQ(run_validate(one + "--skip-check chi2").output.find("exhaustive_roundtrip"), std::string::npos);
    const auto unknown = run_validate(one + "--skip-check chi3");
    EXPECT_EQ(unknown.status, 2);
    EXPECT_NE(unknown.output.find("unknown check 'chi3'"), std::string::npos) << unknown.output;
    const auto misspelt = run_validate(one + "--check chi3 --check roundtrip --skip-check chi2");
    EXPECT_EQ(misspelt.status, 2) << misspelt.output;
    EXPECT_NE(misspelt.output.find("unknown check 'chi3'"), std::string::npos) << misspelt.output;
    const auto none = run_validate(one + "--check chi2 --skip-check chi2");
    EXPECT_EQ(none.status, 2);
    EXPECT_NE(none.output.find("--skip-check leaves no check to run"), std::string::npos) << none.output;
}

// Cases that demonstrate a known flaw stay out of --all, run when asked for,
// and then fail with their numbers.
TEST(Cli, KnownFlawsRunOnlyWhenAskedFor) {
    const auto plain = run_validate("--filter unit_float_mul --check exhaustive");
    EXPECT_EQ(plain.status, 0) << plain.output;
    EXPECT_EQ(plain.output.find("unit_float_mul32 "), std::string::npos) << plain.output;
    const auto named = run_validate("--filter unit_float_mul32 --check exhaustive");
    EXPECT_EQ(named.status, 1) << named.output;
    EXPECT_NE(named.output.find("83886081 distinct, 128 inputs -> 1"), std::string::npos) << named.output;
    const auto flawed = run_validate("--filter lerp_offset --include-flawed --check exhaustive");
    EXPECT_EQ(flawed.status, 1) << flawed.output;
    EXPECT_NE(flawed.output.find("64 inputs -> 101"), std::string::npos) << flawed.output;
}

TEST(Cli, ListShowsCasesAndChecks) {
    const auto r = run_validate("--list");
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.output.find("cosine_hemisphere"), std::string::npos);
    EXPECT_NE(r.output.find("roundtrip"), std::string::npos);
}

TEST(Cli, BadInputExitsTwoWithAMessage) {
    struct Case {
        const char* args;
        const char* message;
    };
    const Case cases[] = {
        {"--all --bogus", "bogus"},
        {"--filter no_such_warp", "no warp case matches 'no_such_warp'"},
        {"--all --check no_such_check", "unknown check 'no_such_check'"},
        {"", "nothing selected"},
        {"--all --samples 0", "--samples: 0 is out of range: give 1,000 to 10,000,000,000"},
        {"--all --samples 1e11", "--samples: 100,000,000,000 is out of range: give 1,000 to 10,000,000,000"},
        {"--all --samples abc", "--samples: 'abc' is not a count (write it as 1000000, 1_000_000, 1e6 or 1M)"},
        {"--all --samples 1.5", "--samples: '1.5' is not a whole number"},
        {"--all --alpha 2", "--alpha: 2 is out of range: give 1e-12 to 0.5"},
        {"--all --alpha nan", "'nan' is not a finite number"},
        {"--all --time-budget nan", "'nan' is not a finite number"},
        {"--all --time-budget 0", "--time-budget: 0 is out of range: give 0.1 to 86400 (seconds)"},
        {"--all --memory-limit 8G", "--memory-limit: 8,000,000,000 is out of range: give 0 to 1,073,741,824 (MiB)"},
        {"--all --seed 18446744073709551616",
         "'18446744073709551616' is not a seed: give a whole number from 0 to 18,446,744,073,709,551,615"},
        {"--all --seed 12x", "is not a seed"},
        {"--all --threads -3", "--threads: '-3' is not a count"},
        {"--all --threads 2000", "--threads: 2,000 is out of range: give 0 to 1,024"},
        {"--all --sampels 10", "unknown option '--sampels' (did you mean '--samples'?)"},
        {"--all --jsn=out.json", "unknown option '--jsn' (did you mean '--json'?)"},
        {"--all --progress sometimes", "--progress"},
        {"--filter unifrom_cone", "no warp case matches 'unifrom_cone' (did you mean 'uniform_cone'?)"},
        {"--filter 'uniform_cone[cos_theta_max=0.4]'",
         "no warp case matches 'uniform_cone[cos_theta_max=0.4]' (did you mean 'uniform_cone[cos_theta_max=0.3]'?)"},
        {"--all --check chi3", "unknown check 'chi3' (did you mean 'chi2'?); the checks are: consistency"},
        {"--all --report a.html --report-on-failure b.html", "--report and --report-on-failure exclude each other"},
        {"--all --report /nonexistent/dir/r.html", "cannot write '/nonexistent/dir/r.html'"},
        {"--all --json /", "cannot write '/'"},
        {"--all --filter cone", "exclude each other"},
    };
    for (const Case& c : cases) {
        const auto r = run_validate(c.args);
        EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
    }
}

// A full case name with commas in its parameters is one filter, not three.
TEST(Cli, FilterIsTakenVerbatim) {
    const auto r =
        run_validate("--filter 'trowbridge_reitz_visible[ax=0.3,ay=0.05,theta_o=60]' --check roundtrip --samples 10000");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("1 checks: 1 passed"), std::string::npos) << r.output;
}

namespace fs = std::filesystem;

std::string contents(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

constexpr const char* kQuickRun = "--filter uniform_cone --check roundtrip --samples 10000 ";

TEST(CliOutputs, SymlinkIsWrittenThroughAndPermissionsAreKept) {
    testing::TempDir scratch;
    const std::string target = scratch.file("results.json"), link = scratch.file("latest.json");
    { std::ofstream(target) << "old"; }
    ::chmod(target.c_str(), 0600);
    fs::create_symlink(target, link);
    const auto r = run_validate(std::string(kQuickRun) + "--json " + link);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::is_symlink(link)) << "the link stays a link";
    EXPECT_NE(contents(target).find("\"results\""), std::string::npos) << contents(target);
    struct stat st {};
    ASSERT_EQ(::stat(target.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600u);
}

TEST(CliOutputs, SpecialFilesAndClashesAreRefusedBeforeTheRun) {
    testing::TempDir scratch;
    const std::string fifo = scratch.file("fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string a = scratch.file("a.json");
    fs::create_symlink(a, scratch.file("b.json"));
    struct Case {
        std::string args, message;
    };
    const Case cases[] = {
        {"--json " + fifo, "not a regular file (a device, FIFO or socket)"},
        {"--junit /dev/null", "not a regular file"},
        {"--json " + a + " --junit " + (scratch.path() / "." / "a.json").string(), "is the same file as another output"},
        {"--json " + a + " --report " + scratch.file("b.json"), "is the same file as another output"},
        {"--json - --junit -", "only one output can be '-'"},
    };
    for (const Case& c : cases) {
        const auto r = run_validate(std::string(kQuickRun) + c.args);
        EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_EQ(r.output.find("roundtrip"), std::string::npos) << "no check ran: " << r.output;
    }
}

TEST(CliOutputs, DashIsStandardOutput) {
    const auto r = testing::run_command("{ " + std::string(WARPCHECK_VALIDATE_EXE) + " " + kQuickRun + "--json - 2>/dev/null; }");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.rfind("{", 0), 0u) << "only the JSON on stdout: " << r.output.substr(0, 200);
}

// Output names are checked as the write will use them: one of 250 bytes (whose
// temporary name is longer than 255) is written, one of 256 is refused before
// the run. Both once failed after the run.
TEST(CliOutputs, LongNamesAreWrittenOrRefusedBeforeTheRun) {
    testing::TempDir scratch;
    const std::string fits = scratch.file(std::string(245, 'a') + ".json");
    const auto written = run_validate(std::string(kQuickRun) + "--json " + fits);
    EXPECT_EQ(written.status, 0) << written.output;
    EXPECT_NE(contents(fits).find("\"results\""), std::string::npos);
    const auto refused = run_validate(std::string(kQuickRun) + "--json " + scratch.file(std::string(256, 'b')));
    EXPECT_EQ(refused.status, 2) << refused.output;
    EXPECT_NE(refused.output.find("the name is longer than the 255 bytes"), std::string::npos) << refused.output;
    EXPECT_EQ(refused.output.find("roundtrip"), std::string::npos) << "no check ran: " << refused.output;
}

// The run's settings are in its JSON, --strict among them.
TEST(CliOutputs, JsonRecordsStrict) {
    for (const char* strict : {"", "--strict "}) {
        const auto r = testing::run_command("{ " + std::string(WARPCHECK_VALIDATE_EXE) + " " + kQuickRun + strict +
                                            "--json - 2>/dev/null; }");
        ASSERT_EQ(r.status, 0) << r.output;
        EXPECT_NE(r.output.find(*strict ? "\"strict\":true" : "\"strict\":false"), std::string::npos)
            << strict << r.output.substr(0, 400);
    }
}

TEST(Cli, HelpAndVersionExitZero) {
    const auto help = run_validate("--help");
    EXPECT_EQ(help.status, 0);
    // The limits in words, without CLI11's validator names.
    EXPECT_NE(help.output.find("--samples N=1000000"), std::string::npos) << help.output;
    // (--help wraps its lines: the words, each run of spaces and newlines read as one space.)
    const std::string words = std::regex_replace(help.output, std::regex("\\s+"), " ");
    EXPECT_NE(words.find("1,000 to 10,000,000,000 (1e6, 10M and 1_000_000 are read)"), std::string::npos);
    for (const char* noise : {"UINT", "FLOAT", "TEXT", " in [", "FINITE", ":SEED", "AND"})
        EXPECT_EQ(help.output.find(noise), std::string::npos) << noise << " in --help:\n" << help.output;
    const auto v = run_validate("--version");
    EXPECT_EQ(v.status, 0);
    EXPECT_NE(v.output.find("warpcheck"), std::string::npos);
}

// --help fits 100 columns: each description is wrapped under its first line
// (CLI11 printed them on one line, up to 357 columns).
TEST(Cli, HelpLinesFitOneHundredColumns) {
    const auto help = run_validate("--help");
    ASSERT_EQ(help.status, 0);
    std::istringstream lines(help.output);
    std::size_t count = 0;
    for (std::string line; std::getline(lines, line); ++count) EXPECT_LE(line.size(), 100u) << line;
    EXPECT_GT(count, 40u);
    EXPECT_NE(help.output.find("--no-isolation"), std::string::npos);
}

// What people type by mistake gets an answer that helps: an option written
// as a word, a family with nothing near it, a negative seed.
TEST(Cli, MistakesGetAnswersThatHelp) {
    const auto all = run_validate("all");
    EXPECT_EQ(all.status, 2) << all.output;
    EXPECT_NE(all.output.find("'all' is not an argument: options start with '--' (did you mean '--all'?)"),
              std::string::npos)
        << all.output;
    const auto word = run_validate("cone");
    EXPECT_EQ(word.status, 2) << word.output;
    EXPECT_NE(word.output.find("unexpected argument 'cone': validate takes options only (a case goes after --filter, "
                               "e.g. --filter 'cone')"),
              std::string::npos)
        << word.output;
    // Nothing is within a third of 'beckman' (the nearest, lambertian, is 3 edits away): no suggestion.
    const auto beckman = run_validate("--filter beckman");
    EXPECT_EQ(beckman.status, 2) << beckman.output;
    EXPECT_NE(beckman.output.find("no warp case matches 'beckman'; 'validate --list' shows them all"),
              std::string::npos)
        << beckman.output;
    EXPECT_EQ(beckman.output.find("lambertian"), std::string::npos) << beckman.output;
    const auto seed = testing::run_command("WARPCHECK_SEED=-1 " + std::string(WARPCHECK_VALIDATE_EXE) +
                                           " --all --settings-from-environment");
    EXPECT_EQ(seed.status, 2) << seed.output;
    EXPECT_NE(seed.output.find("WARPCHECK_SEED='-1' is not a seed: give a whole number from 0 to "
                               "18,446,744,073,709,551,615"),
              std::string::npos)
        << seed.output;
}

// The progress display and the summary count the same checks: those that
// ran, the n/a rows apart (the progress said 459 while the summary said 463).
TEST(Cli, ProgressAndSummaryCountTheSameChecks) {
    const auto r = run_validate("--filter 'smooth_dielectric[eta=1.5,theta_o=60]' --samples 1e4 --progress bar");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("n/a    bsdf_reciprocity"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("/4 "), std::string::npos) << "the progress counts 4 jobs:\n" << r.output;
    EXPECT_EQ(r.output.find("/5 "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("4 checks: 4 passed, 0 failed, 0 errors; 1 n/a, not run in "),
              std::string::npos)
        << r.output;
}

// validate re-executes itself once with huge pages asked of glibc's malloc
// (validate/cli/cli.h): whatever GLIBC_TUNABLES held before, it runs once, prints
// once and keeps the user's own settings; the same rows come out either way.
TEST(Cli, HugePagesReexecRunsOnceAndChangesNoResult) {
    const std::string exe = WARPCHECK_VALIDATE_EXE;
    for (const std::string env : {"env -u GLIBC_TUNABLES ", "GLIBC_TUNABLES=glibc.malloc.hugetlb=0 ",
                                  "GLIBC_TUNABLES=glibc.malloc.check=0 "}) {
        const auto version = testing::run_command(env + exe + " --version");
        EXPECT_EQ(version.status, 0) << env << version.output;
        const std::size_t first = version.output.find("warpcheck");
        ASSERT_NE(first, std::string::npos) << env << version.output;
        EXPECT_EQ(version.output.find("warpcheck", first + 1), std::string::npos) << env << "printed twice:\n"
                                                                                   << version.output;
    }
    testing::TempDir scratch;
    const std::string run = std::string(kQuickRun) + "--progress none --json ";
    const auto with = testing::run_command("env -u GLIBC_TUNABLES " + exe + " " + run + scratch.file("a.json"));
    const auto without =
        testing::run_command("GLIBC_TUNABLES=glibc.malloc.hugetlb=0 " + exe + " " + run + scratch.file("b.json"));
    ASSERT_EQ(with.status, 0) << with.output;
    ASSERT_EQ(without.status, 0) << without.output;
    const auto rows = [&](const char* name) {
        std::ifstream in(scratch.file(name));
        return nlohmann::json::parse(in)["results"];
    };
    nlohmann::json a = rows("a.json"), b = rows("b.json");
    ASSERT_FALSE(a.empty());
    for (auto* r : {&a, &b})
        for (auto& row : *r) row.erase("seconds"), row.erase("phases");
    EXPECT_EQ(a, b);
}

// The time budget and memory limit reach a ctest run too (and the
// GoogleTest adapter, tests/gtest_adapter/); an invalid one names its variable.
TEST(Cli, TimeBudgetAndMemoryLimitFromTheEnvironment) {
    const std::string run = std::string(kQuickRun) + "--progress none --settings-from-environment";
    const auto bad = testing::run_command("WARPCHECK_TIME_BUDGET=0 " + std::string(WARPCHECK_VALIDATE_EXE) + " " + run);
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_NE(bad.output.find("WARPCHECK_TIME_BUDGET='0': 0 is out of range: give 0.1 to 86400 (seconds)"),
              std::string::npos)
        << bad.output;
    const auto memory = testing::run_command("WARPCHECK_MEMORY_LIMIT=lots " + std::string(WARPCHECK_VALIDATE_EXE) +
                                             " " + run);
    EXPECT_EQ(memory.status, 2) << memory.output;
    EXPECT_NE(memory.output.find("WARPCHECK_MEMORY_LIMIT='lots' is not a count"), std::string::npos) << memory.output;
    const auto good = testing::run_command("WARPCHECK_TIME_BUDGET=30 WARPCHECK_MEMORY_LIMIT=4096 " +
                                           std::string(WARPCHECK_VALIDATE_EXE) + " " + run);
    EXPECT_EQ(good.status, 0) << good.output;
}

// An output that is a loop of symbolic links: a usage error before the run,
// the links left as they were (the loop was replaced by a file, exit 0).
TEST(Cli, OutputLoopOfSymlinksIsAUsageError) {
    testing::TempDir scratch;
    fs::create_symlink("b.json", scratch.path() / "a.json");
    fs::create_symlink("a.json", scratch.path() / "b.json");
    const auto r = run_validate(std::string(kQuickRun) + "--progress none --json " + scratch.file("a.json"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("symbolic links form a loop"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::is_symlink(scratch.path() / "a.json"));
}

// Counts as people type them reach the run unchanged in meaning.
TEST(Cli, CountsAsPeopleTypeThem) {
    for (const char* samples : {"1e4", "10k", "10_000", "0.01M"}) {
        const auto r = run_validate(std::string("--filter uniform_cone --check roundtrip --progress none --samples ") +
                                    samples);
        EXPECT_EQ(r.status, 0) << samples << "\n" << r.output;
        EXPECT_NE(r.output.find("(seed 1, 10000 samples"), std::string::npos) << samples << "\n" << r.output;
    }
}

// A program built on warpcheck::main (here: validate under another name) says
// its own name in every message.
TEST(Cli, MessagesSayTheProgramsOwnName) {
    testing::TempDir scratch;
    const std::string renamed = scratch.file("validate_my_warps");
    fs::create_symlink(WARPCHECK_VALIDATE_EXE, renamed);
    for (const char* args : {"--all --samples 1", "--bogus", "--filter nothing_like_it"}) {
        const auto r = testing::run_command(renamed + " " + args);
        EXPECT_EQ(r.status, 2) << args;
        EXPECT_EQ(r.output.rfind("validate_my_warps: ", 0), 0u) << args << "\n" << r.output;
        EXPECT_EQ(r.output.find("validate:"), std::string::npos) << args << "\n" << r.output;
    }
    const auto help = testing::run_command(renamed + " --help");
    EXPECT_NE(help.output.find("Usage: validate_my_warps"), std::string::npos) << help.output;
}

TEST(Cli, FailuresOnlyOnAnAllPassRunSaysSo) {
    const auto r = run_validate(std::string(kQuickRun) + "--progress none --failures-only");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("No failures: all 3 checks that ran passed."), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("key figure"), std::string::npos) << "no empty header:\n" << r.output;
}

// Each output written says where; --report-on-failure writes only for a failure.
TEST(CliOutputs, WrittenFilesAreNamedAndEvidenceOnlyOnFailure) {
    testing::TempDir scratch;
    const std::string json = scratch.file("r.json"), evidence = scratch.file("evidence.html");
    const auto pass = run_validate(std::string(kQuickRun) + "--progress none --json " + json +
                                   " --report-on-failure " + evidence);
    EXPECT_EQ(pass.status, 0) << pass.output;
    EXPECT_NE(pass.output.find("JSON results written to " + json + "\n"), std::string::npos) << pass.output;
    EXPECT_FALSE(fs::exists(evidence)) << "no evidence for a passing run";
    const auto fail = run_validate("--filter lerp_offset --include-flawed --check exhaustive --progress none "
                                   "--report-on-failure " + evidence);
    EXPECT_EQ(fail.status, 1) << fail.output;
    EXPECT_NE(fail.output.find("HTML report written to " + evidence), std::string::npos) << fail.output;
    EXPECT_NE(contents(evidence).find("lerp_offset"), std::string::npos);
}

// --settings-from-environment (what warpcheck_discover_tests runs): the
// variables replace the options; an invalid one is an error that names it.
TEST(Cli, SettingsFromTheEnvironment) {
    const std::string run = std::string(kQuickRun) + "--progress none --settings-from-environment";
    const auto good = testing::run_command("WARPCHECK_SAMPLES=2e4 WARPCHECK_SEED=5 " +
                                           std::string(WARPCHECK_VALIDATE_EXE) + " " + run);
    EXPECT_EQ(good.status, 0) << good.output;
    EXPECT_NE(good.output.find("(seed 5, 20000 samples"), std::string::npos) << good.output;
    const auto bad = testing::run_command("WARPCHECK_ALPHA=2 " + std::string(WARPCHECK_VALIDATE_EXE) + " " + run);
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_NE(bad.output.find("validate: WARPCHECK_ALPHA='2': 2 is out of range: give 1e-12 to 0.5"), std::string::npos)
        << bad.output;
    const auto ignored = testing::run_command("WARPCHECK_SAMPLES=lots " + std::string(WARPCHECK_VALIDATE_EXE) + " " +
                                              kQuickRun + "--progress none");
    EXPECT_EQ(ignored.status, 0) << "without the flag the environment is not read:\n" << ignored.output;
}

// In a CI log (stderr not a terminal), a failure is shown as soon as its job
// ends, before the table.
TEST(Cli, ProgressLogShowsFailuresAsTheyHappen) {
    const auto r = run_validate("--filter lerp_offset --include-flawed --check exhaustive --check consistency");
    EXPECT_EQ(r.status, 1) << r.output;
    const std::size_t live = r.output.find("validate: FAIL   exhaustive  lerp_offset");
    EXPECT_NE(live, std::string::npos) << r.output;
    EXPECT_LT(live, r.output.find("key figure")) << r.output;
}

}  // namespace
}  // namespace warpcheck
