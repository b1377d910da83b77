// function_length: lists every function body in the given C++ files that is
// longer than a threshold, as clang-tidy's readability-function-size measures it
// (the line of the closing brace minus the line of the opening one), and exits
// 1 if there is any. The ctest function_length runs it over every production
// file (sampling/, chi2/, validate/, reports/), in well under a second, where
// clang-tidy took four minutes of a CI core to parse every translation unit.
//
// It reads the code as tokens, not as an AST: comments, string and character
// literals (raw strings and digit separators included) and preprocessor lines
// are skipped, and a brace at namespace or class scope opens a function body
// when what precedes it can only be a function's head: ") {", ") const {",
// "-> T {", "requires C {", or a constructor's member initialisers
// ": a_(x), b_{y} {". An "=" before the brace (a lambda or a braced
// initialiser), and class, struct, union, enum and namespace heads are not
// bodies. tests/lint/test_function_length.cpp holds it to that on the shapes
// the project writes, and `--compare` mode was checked against clang-tidy on
// the whole tree (the figures are in the commit that added this file).
//
// Usage: function_length [--threshold N] [--all] PATH...
//   PATH   a file, or a folder whose .h and .cpp files are read (recursively);
//   --all  prints every body with its length (for comparison with clang-tidy).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "lint/function_length.h"

namespace {

/// The files a path names: itself, or a folder's .h and .cpp files, sorted.
std::vector<std::string> sources(const std::string& path) {
    namespace fs = std::filesystem;
    if (!fs::is_directory(path)) return {path};
    std::vector<std::string> out;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(path))
        if (e.is_regular_file() && (e.path().extension() == ".h" || e.path().extension() == ".cpp"))
            out.push_back(e.path().string());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    int threshold = 80;
    bool all = false;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--threshold" && i + 1 < argc) {
            threshold = std::atoi(argv[++i]);
        } else if (arg == "--all") {
            all = true;
        } else if (!arg.empty() && arg[0] == '-') {
            std::fprintf(stderr, "usage: function_length [--threshold N] [--all] PATH...\n");
            return 2;
        } else {
            for (std::string& f : sources(arg)) files.push_back(std::move(f));
        }
    }
    if (files.empty() || threshold <= 0) {
        std::fprintf(stderr, "usage: function_length [--threshold N] [--all] PATH...\n");
        return 2;
    }
    int offenders = 0;
    for (const std::string& path : files) {
        std::ifstream in(path, std::ios::binary);
        if (!in) {
            std::fprintf(stderr, "function_length: cannot read %s\n", path.c_str());
            return 2;
        }
        std::ostringstream text;
        text << in.rdbuf();
        for (const lint::FunctionBody& f : lint::function_bodies(text.str())) {
            const bool over = f.lines > threshold;
            if (over) ++offenders;
            if (over || all)
                std::printf("%s:%d: %s (%d lines)%s\n", path.c_str(), f.name_line, f.name.c_str(), f.lines,
                            over ? " over the threshold" : "");
        }
    }
    if (offenders > 0) {
        std::printf("%d function(s) longer than %d lines\n", offenders, threshold);
        return 1;
    }
    std::printf("function_length: %zu files, no function over %d lines\n", files.size(), threshold);
    return 0;
}
