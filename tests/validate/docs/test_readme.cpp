// Keeps the READMEs honest: every code block marked <!-- snippet: PATH --> in
// README.md or a folder's README.md must appear, character for character, in
// the file PATH (relative to the repository). The walkthrough's warp must also
// be registered and pass its checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/run_command.h"

namespace warpcheck {
namespace {

std::string read_file(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

struct Snippet {
    std::string path;
    std::string code;
};

/// README.md and the README.md of every folder of the sources and tests.
std::vector<std::string> readme_paths() {
    namespace fs = std::filesystem;
    const fs::path root(WARPCHECK_SOURCE_DIR);
    std::vector<std::string> paths{(root / "README.md").string()};
    for (const char* folder : {"sampling", "chi2", "reports", "validate", "tests"}) {
        for (const auto& entry : fs::recursive_directory_iterator(root / folder)) {
            if (entry.path().filename() == "README.md") paths.push_back(entry.path().string());
        }
    }
    return paths;
}

void add_snippets(const std::string& readme, std::vector<Snippet>& snippets) {
    const std::string marker = "<!-- snippet: ";
    for (std::size_t at = readme.find(marker); at != std::string::npos; at = readme.find(marker, at + 1)) {
        const std::size_t path_end = readme.find(" -->", at);
        const std::size_t fence = readme.find("```", path_end);
        const std::size_t code_start = readme.find('\n', fence) + 1;
        const std::size_t code_end = readme.find("```", code_start);
        snippets.push_back({readme.substr(at + marker.size(), path_end - at - marker.size()),
                            readme.substr(code_start, code_end - code_start)});
    }
}

std::vector<Snippet> readme_snippets() {
    std::vector<Snippet> snippets;
    for (const std::string& path : readme_paths()) add_snippets(read_file(path), snippets);
    return snippets;
}

TEST(Readme, SnippetsMatchTheFilesTheyQuote) {
    const auto snippets = readme_snippets();
    ASSERT_GE(snippets.size(), 15u);  // README.md and validate/api/README.md quote 16
    for (const auto& s : snippets) {
        // A path, not std::string + "/" + ...: GCC 12 warned of a bogus
        // array-bounds overflow in that inlined concatenation (-Werror) for some
        // lengths of WARPCHECK_SOURCE_DIR, as a fresh clone's in /tmp.
        const std::string file = read_file((std::filesystem::path(WARPCHECK_SOURCE_DIR) / s.path).string());
        ASSERT_FALSE(file.empty()) << s.path;
        EXPECT_NE(file.find(s.code), std::string::npos) << "README snippet no longer matches " << s.path << ":\n"
                                                        << s.code;
    }
}

/// A block of output a README quotes: the arguments of the `validate` run it
/// comes from, and its lines.
struct QuotedRun {
    std::string readme, args;
    std::vector<std::string> lines;
};

/// Every code block marked <!-- output of: validate ARGS --> in a README.
std::vector<QuotedRun> quoted_runs() {
    const std::string marker = "<!-- output of: validate ";
    std::vector<QuotedRun> runs;
    for (const std::string& path : readme_paths()) {
        const std::string readme = read_file(path);
        for (std::size_t at = readme.find(marker); at != std::string::npos; at = readme.find(marker, at + 1)) {
            const std::size_t args_end = readme.find(" -->", at);
            const std::size_t code_start = readme.find('\n', readme.find("```", args_end)) + 1;
            const std::size_t code_end = readme.find("```", code_start);
            QuotedRun run{path, readme.substr(at + marker.size(), args_end - at - marker.size()), {}};
            std::istringstream block(readme.substr(code_start, code_end - code_start));
            for (std::string line; std::getline(block, line);) run.lines.push_back(line);
            runs.push_back(std::move(run));
        }
    }
    return runs;
}

// The table a README shows is the table its command prints: each quoted line
// is a line of a real run (the same seed, so the same figures, bit for bit).
TEST(Readme, QuotedOutputIsWhatItsCommandPrints) {
    const std::vector<QuotedRun> runs = quoted_runs();
    ASSERT_GE(runs.size(), 1u) << "README.md quotes the table of a run";
    for (const QuotedRun& run : runs) {
        ASSERT_GE(run.lines.size(), 3u) << run.readme << ": " << run.args;
        const auto r = testing::run_validate(run.args + " --color never --progress none");
        ASSERT_NE(r.status, 2) << run.args << "\n" << r.output;
        std::istringstream out(r.output);
        std::vector<std::string> printed;
        for (std::string line; std::getline(out, line);) printed.push_back(line);
        for (const std::string& line : run.lines)
            EXPECT_NE(std::find(printed.begin(), printed.end(), line), printed.end())
                << run.readme << " quotes a line that `validate " << run.args << "` does not print:\n"
                << line << "\nIt prints:\n"
                << r.output;
    }
}

// "Take the next free rank (the built-in families use 10 to N)": N is the
// largest rank a built-in family takes.
TEST(Readme, BuiltinRanksAreAsTheReadmeSays) {
    namespace fs = std::filesystem;
    int largest = 0;
    const std::string marker = "WARPCHECK_BUILTIN_CASES(";
    for (const auto& entry : fs::directory_iterator(fs::path(WARPCHECK_SOURCE_DIR) / "validate" / "cases")) {
        const std::string text = read_file(entry.path().string());
        for (std::size_t at = text.find(marker); at != std::string::npos; at = text.find(marker, at + 1))
            if (std::isdigit(static_cast<unsigned char>(text[at + marker.size()])))
                largest = std::max(largest, std::stoi(text.substr(at + marker.size())));
    }
    ASSERT_GT(largest, 0);
    const std::string readme = read_file((std::filesystem::path(WARPCHECK_SOURCE_DIR) / "README.md").string());
    EXPECT_NE(readme.find("families use 10 to " + std::to_string(largest) + ")"), std::string::npos)
        << "README.md names another range of ranks than 10 to " << largest;
}

TEST(Readme, WalkthroughWarpPassesItsChecks) {
    const auto r = testing::run_validate("--filter bilinear --samples 200000 --color never");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("bilinear[w00=1,w10=4,w01=0.5,w11=2]"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace warpcheck
