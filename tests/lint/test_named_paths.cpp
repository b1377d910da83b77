// The named-paths lint (tests/lint/named_paths.h) on the ways the tree's
// docs and comments name paths: each path of a room is found with its line,
// and installed include paths, patterns and parts of longer paths are not.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "lint/named_paths.h"

namespace {

std::vector<std::string> found(std::string_view text) {
    std::vector<std::string> out;
    for (const lint::NamedPath& p : lint::named_paths(text)) out.push_back(p.path + ":" + std::to_string(p.line));
    return out;
}

TEST(NamedPaths, FindsEachRoomsPathsWithTheirLines) {
    EXPECT_EQ(found("// see validate/api/warp_case.h.\n// and (chi2/quadrature.h, tests/lint/)\n.ci/run"),
              (std::vector<std::string>{"validate/api/warp_case.h:1", "chi2/quadrature.h:2", "tests/lint/:2",
                                        ".ci/run:3"}));
    EXPECT_EQ(found("[api/CHANGELOG.md](reports/README.md) `sampling/bsdf.h`"),
              (std::vector<std::string>{"reports/README.md:1", "sampling/bsdf.h:1"}));
}

TEST(NamedPaths, InstalledIncludePathsPatternsAndLongerPathsAreNotTaken) {
    EXPECT_TRUE(found("#include <validate/external.h>").empty());
    EXPECT_TRUE(found("sampling/bsdf_*.h and tests/<folder>/x and chi2/power{n=4}").empty());
    EXPECT_TRUE(found("/path/to/tests/x.cpp build/validate/validate https://x.org/chi2/a.h").empty());
    EXPECT_TRUE(found("myvalidate/x.h").empty());
}

}  // namespace
