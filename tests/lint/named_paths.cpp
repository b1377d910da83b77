// Every path of the tree named in the docs, comments and scripts exists
// (tests/lint/named_paths.h says which words are paths). Run from the
// project's root: named_paths [ROOT]. Prints each missing one as
// file:line: path and exits 1; exits 0 when all exist.
//
// Left out, each for its reason:
// - validate/api/CHANGELOG.md, validate/api/old_paths/ and tests/upgrade/
//   name the old paths on purpose (what moved, and the headers that forward);
// - kGenerated: paths a build or a user's run creates, named as such.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "lint/named_paths.h"

namespace fs = std::filesystem;

namespace {

/// Files and folders not read (above says why).
const std::vector<std::string> kNotRead = {"validate/api/CHANGELOG.md", "validate/api/old_paths/", "tests/upgrade/"};

/// Paths that are not in the source tree by design.
const std::vector<std::string> kGenerated = {
    "tests/reports/render/report.png",  // the rendered report, in the build tree (tests/CMakeLists.txt)
    "tests/python/tmp",                 // pytest's folders, in the build tree
    "tests/test_mine.py",               // a user's test file, in the Python README's example output
    "tests/hard/hard_warps_fpr",        // a program of the build tree (tests/hard/hard_warps_fpr.cpp)
};

bool read_here(const std::string& rel) {
    static const std::vector<std::string> kExtensions = {".md", ".h", ".cpp", ".txt", ".cmake", ".sh", ".py", ".json"};
    for (const std::string& skip : kNotRead)
        if (rel.rfind(skip, 0) == 0) return false;
    if (rel.rfind(".ci/", 0) == 0) return true;
    return std::any_of(kExtensions.begin(), kExtensions.end(), [&](const std::string& e) {
        return rel.size() > e.size() && rel.compare(rel.size() - e.size(), e.size(), e) == 0;
    });
}

std::vector<std::string> files_of(const fs::path& root) {
    std::vector<std::string> out = {"README.md", "CMakeLists.txt", "CMakePresets.json"};
    for (std::string_view room : lint::kRooms) {
        const fs::path dir = root / std::string(room);
        if (!fs::is_directory(dir)) continue;
        for (const auto& entry : fs::recursive_directory_iterator(dir)) {
            if (!entry.is_regular_file()) continue;
            const std::string rel = fs::relative(entry.path(), root).generic_string();
            if (read_here(rel)) out.push_back(rel);
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    const fs::path root = argc > 1 ? fs::path(argv[1]) : fs::current_path();
    int missing = 0;
    std::size_t named = 0;
    for (const std::string& rel : files_of(root)) {
        std::ifstream in(root / rel, std::ios::binary);
        if (!in) continue;
        std::ostringstream text;
        text << in.rdbuf();
        for (const lint::NamedPath& p : lint::named_paths(text.str())) {
            ++named;
            const bool generated = std::find(kGenerated.begin(), kGenerated.end(), p.path) != kGenerated.end();
            // From the root, or (a README's link) from the file's own folder.
            const bool exists =
                fs::exists(root / p.path) || fs::exists(root / fs::path(rel).parent_path() / p.path);
            if (exists || generated) continue;
            std::printf("%s:%d: %s does not exist\n", rel.c_str(), p.line, p.path.c_str());
            ++missing;
        }
    }
    std::printf("named_paths: %zu paths named, %d missing\n", named, missing);
    return missing == 0 ? 0 : 1;
}
