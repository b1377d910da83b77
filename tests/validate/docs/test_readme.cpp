// Keeps the READMEs honest: every code block marked <!-- snippet: PATH --> in
// README.md or a folder's README.md must appear, character for character, in
// the file PATH (relative to the repository). The walkthrough's warp must also
// be registered and pass its checks.
#include <gtest/gtest.h>

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
        const std::string file = read_file(std::string(WARPCHECK_SOURCE_DIR) + "/" + s.path);
        ASSERT_FALSE(file.empty()) << s.path;
        EXPECT_NE(file.find(s.code), std::string::npos) << "README snippet no longer matches " << s.path << ":\n"
                                                        << s.code;
    }
}

TEST(Readme, WalkthroughWarpPassesItsChecks) {
    const auto r = testing::run_validate("--filter bilinear --samples 200000 --color never");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("bilinear[w00=1,w10=4,w01=0.5,w11=2]"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace warpcheck
