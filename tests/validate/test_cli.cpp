// The validate command: exit statuses and messages for good and bad input.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/run_command.h"

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
        {"--all --samples 0", "samples"},
        {"--all --samples abc", "samples"},
        {"--all --alpha 2", "alpha"},
        {"--all --alpha nan", "'nan' is not a finite number"},
        {"--all --time-budget nan", "'nan' is not a finite number"},
        {"--all --seed 18446744073709551616", "is not a seed: an integer from 0 to 18446744073709551615"},
        {"--all --seed 12x", "is not a seed"},
        {"--all --threads -3", "threads"},
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

// A scratch folder for the output tests, removed afterwards.
struct Scratch {
    fs::path dir = fs::temp_directory_path() / ("warpcheck-cli-" + std::to_string(::getpid()));
    Scratch() {
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~Scratch() {
        std::error_code ignored;
        fs::remove_all(dir, ignored);
    }
    std::string operator/(const std::string& name) const { return (dir / name).string(); }
};

std::string contents(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

constexpr const char* kQuickRun = "--filter uniform_cone --check roundtrip --samples 10000 ";

TEST(CliOutputs, SymlinkIsWrittenThroughAndPermissionsAreKept) {
    Scratch scratch;
    const std::string target = scratch / "results.json", link = scratch / "latest.json";
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
    Scratch scratch;
    const std::string fifo = scratch / "fifo";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string a = scratch / "a.json";
    fs::create_symlink(a, scratch / "b.json");
    struct Case {
        std::string args, message;
    };
    const Case cases[] = {
        {"--json " + fifo, "not a regular file (a device, FIFO or socket)"},
        {"--junit /dev/null", "not a regular file"},
        {"--json " + a + " --junit " + (scratch.dir / "." / "a.json").string(), "is the same file as another output"},
        {"--json " + a + " --report " + scratch / "b.json", "is the same file as another output"},
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
    Scratch scratch;
    const std::string fits = scratch / (std::string(245, 'a') + ".json");
    const auto written = run_validate(std::string(kQuickRun) + "--json " + fits);
    EXPECT_EQ(written.status, 0) << written.output;
    EXPECT_NE(contents(fits).find("\"results\""), std::string::npos);
    const auto refused = run_validate(std::string(kQuickRun) + "--json " + scratch / std::string(256, 'b'));
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
    EXPECT_EQ(run_validate("--help").status, 0);
    const auto v = run_validate("--version");
    EXPECT_EQ(v.status, 0);
    EXPECT_NE(v.output.find("warpcheck"), std::string::npos);
}

}  // namespace
}  // namespace warpcheck
