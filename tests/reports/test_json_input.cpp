// Reading JSON results back (what validate --merge does): every field of every
// result comes back, so the document written again is the same text; a file
// that is not a warpcheck results document is a clear error.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "reports/json_input.h"
#include "reports/render.h"
#include "tests/reports/sample_run.h"

namespace warpcheck {
namespace {

using ::testing::HasSubstr;

TEST(JsonInput, ReadBackAndWrittenAgainIsTheSameDocument) {
    RunResult run = testing::sample_everything();
    run.info.shard_index = 2;
    run.info.shard_count = 3;
    run.info.run_jobs = 17;
    run.results[0].figures.push_back({"nan", std::numeric_limits<double>::quiet_NaN()});
    run.results[0].figures.push_back({"tiny", 4.9406564584124654e-324});
    const std::string text = render_json(run);
    const RunResult back = parse_json_results(text);
    EXPECT_EQ(render_json(back), text);
    EXPECT_EQ(back.info.shard_index, 2u);
    EXPECT_EQ(back.info.run_jobs, 17u);
    ASSERT_EQ(back.results.size(), run.results.size());
    EXPECT_EQ(back.results[0].figure("tiny"), 4.9406564584124654e-324);
    EXPECT_EQ(back.results[0].stream_seed, run.results[0].stream_seed);
}

TEST(JsonInput, OtherDocumentsAreClearErrors) {
    const std::string good = render_json(testing::sample_pass_and_fail());
    const auto error = [](const std::string& text) {
        try {
            parse_json_results(text);
        } catch (const JsonInputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_THAT(error("{\"results\": ["), HasSubstr("not a JSON document"));
    EXPECT_THAT(error("{}"), HasSubstr("not a warpcheck results file"));
    std::string other = good;
    other.replace(other.find("\"schema_version\":1"), 18, "\"schema_version\":9");
    EXPECT_THAT(error(other), HasSubstr("schema_version 9"));
    std::string bad_verdict = good;
    bad_verdict.replace(bad_verdict.find("\"verdict\":\"pass\""), 16, "\"verdict\":\"meh\"");
    EXPECT_THAT(error(bad_verdict), HasSubstr("'meh' is not a verdict"));
}

}  // namespace
}  // namespace warpcheck
