// The GoogleTest adapter's evidence files (validate/gtest/): written in a
// folder of the adapter's own, apart from the ctest integration's, and under
// a name a file system takes however long the case name is.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "support/temp_dir.h"
#include "validate/api/external.h"
#include "validate/gtest/job_tests.h"
#include "validate/gtest/warpcheck_gtest.h"
#include "tests/gtest_adapter/scoped_env.h"

namespace warpcheck {
namespace {

/// The identity on [0,1) with its inverse halved: its round trip fails.
struct HalvedInverse {
    float sample(float u) const { return u; }
    float pdf(float x) const { return x >= 0 && x <= 1 ? 1.0f : 0.0f; }
    float invert(float x) const { return 0.5f * x; }
};

using gtest_adapter_tests::ScopedEnv;

std::string evidence_line(const std::string& message) {
    const std::size_t at = message.find("evidence: ");
    if (at == std::string::npos) return "";
    return message.substr(at + 10, message.find('\n', at) - at - 10);
}

TEST(GtestEvidence, ALongCaseNameStillGetsItsEvidenceFile) {
    testing::TempDir dir;
    const ScopedEnv evidence("WARPCHECK_EVIDENCE_DIR", dir.path().string());
    const ScopedEnv samples("WARPCHECK_SAMPLES", "10000");
    const auto warp = make_warp_case({.family = std::string(300, 'l'),
                                      .params = {{"a", 1}},
                                      .description = "identity, inverse halved, under a name of 306 bytes",
                                      .domain = chi2::Domain::interval(0, 1)},
                                     HalvedInverse{});
    const ::testing::AssertionResult result = gtest::WarpCasePasses("warp", warp);
    ASSERT_FALSE(result);
    const std::string path = evidence_line(result.message());
    ASSERT_FALSE(path.empty()) << result.message();
    ASSERT_FALSE(path.starts_with("not written")) << result.message();
    EXPECT_TRUE(std::filesystem::is_regular_file(path)) << path;
    const std::filesystem::path file(path);
    EXPECT_LE(file.filename().string().size(), 255u);
    EXPECT_TRUE(file.filename().string().starts_with("llll")) << file;
    // In the adapter's own folder, gtest/<test suite>, apart from ctest/ of the ctest integration.
    EXPECT_EQ(file.parent_path(), std::filesystem::absolute(dir.path()) / "gtest" / "GtestEvidence");
}

TEST(GtestEvidence, NamesFitAFileNameAndStayDistinct) {
    gtest::Settings settings;
    settings.evidence_dir = "evidence";
    const std::filesystem::path shortname = gtest::evidence_path(settings, "warpcheck/MyWarps", "power_n_4__chi2");
    EXPECT_EQ(shortname, std::filesystem::absolute("evidence") / "gtest" / "warpcheck_MyWarps" / "power_n_4__chi2.html");
    const std::string stem = std::string(300, 'l');
    const std::string a = gtest::evidence_path(settings, "S", stem + "_a_1__roundtrip").filename().string();
    const std::string b = gtest::evidence_path(settings, "S", stem + "_a_2__roundtrip").filename().string();
    EXPECT_LE(a.size(), 255u);
    EXPECT_LE(b.size(), 255u);
    EXPECT_NE(a, b);
    EXPECT_TRUE(a.ends_with("__roundtrip.html")) << a;
    EXPECT_EQ(gtest::evidence_path(settings, "", "x__chi2").parent_path(),
              std::filesystem::absolute("evidence") / "gtest");
}

}  // namespace
}  // namespace warpcheck
