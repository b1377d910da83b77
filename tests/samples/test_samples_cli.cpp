// validate's options for samples from elsewhere: a run from files end to end, and
// every misuse a usage error (status 2) that says what to do.
#include <string>

#include <gtest/gtest.h>

#include "support/run_command.h"
#include "support/temp_dir.h"
#include "validate/samples/sample_file.h"

namespace warpcheck {
namespace {

using testing::run_validate;

void expect_usage_error(const std::string& args, const std::string& words) {
    const auto r = run_validate(args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << args << "\n" << r.output;
}

TEST(SamplesCli, RecordThenReplayPassesAndComparesBitForBit) {
    testing::TempDir dir;
    const std::string u = dir.file("u.npy"), x = dir.file("x.npy");
    const std::string select = "--filter uniform_disk_polar --check chi2 --samples 1e4 --color never ";
    const auto recorded = run_validate(select + "--record-inputs " + u + " --record-outputs " + x);
    ASSERT_EQ(recorded.status, 0) << recorded.output;
    EXPECT_EQ(read_npy(u).cols, 2u);
    const auto replayed = run_validate(select + "--replay " + u + " " + x + " --json " + dir.file("r.json"));
    EXPECT_EQ(replayed.status, 0) << replayed.output;
    EXPECT_NE(testing::read_file(dir.file("r.json")).find("--replay '" + u + "' '" + x + "'"), std::string::npos)
        << "the rerun line replays";
    const auto same = run_validate("--compare " + x + " " + x + " --inputs " + u + " --color never");
    EXPECT_EQ(same.status, 0) << same.output;
    EXPECT_NE(same.output.find("100% identical"), std::string::npos) << same.output;
    const auto two = run_validate("--two-sample " + x + " " + x + " --filter uniform_disk_polar --color never");
    EXPECT_EQ(two.status, 0) << two.output;
}

TEST(SamplesCli, MisuseIsAUsageErrorThatSaysWhatToDo) {
    testing::TempDir dir;
    const std::string x = dir.file("x.npy");
    NumericArray a;
    a.rows = 4;
    a.cols = 2;
    a.reals = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8};
    write_npy(x, a);
    expect_usage_error("--replay " + x + " " + x, "--replay needs one case: select it with --filter");
    expect_usage_error("--judge-samples " + x + " --filter cone", "needs one case, and --filter selects");
    expect_usage_error("--judge-samples " + x + " --filter cosine_hemisphere", "shape (n, 3), not a float32 array of shape (4, 2)");
    expect_usage_error("--judge-samples " + dir.file("missing.npy") + " --filter cosine_hemisphere", "cannot read");
    expect_usage_error("--judge-samples " + dir.file("x.f32") + " --filter cosine_hemisphere", "--raw-layout 3");
    expect_usage_error("--compare " + x + " " + x + " --raw-layout 5", "not a raw layout");
    expect_usage_error("--record-outputs " + x + " --filter cosine_hemisphere", "go with a run of samples");
    expect_usage_error("--record-outputs " + x + " --judge-samples " + x + " --filter cosine_hemisphere",
                       "--record-outputs goes with --record-inputs");
    expect_usage_error("--max-ulps 3 --two-sample " + x + " " + x, "go with --compare");
    expect_usage_error("--record-inputs " + x + " --replay " + x + " " + x + " --filter cosine_hemisphere",
                       "separate runs");
}

}  // namespace
}  // namespace warpcheck
