// A pass that could not have seen its stated effect (CheckResult::weak, issue
// 34) is shown as "weak" in every view, never as a plain pass, and is not a
// failure; the runner clears it on a row it fails.
#include <sstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "reports/render.h"
#include "reports/terminal_table.h"
#include "tests/reports/json_schema_check.h"
#include "tests/reports/sample_run.h"
#include "support/temp_dir.h"

namespace warpcheck {
namespace {

using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::Not;
using namespace warpcheck::testing;

RunResult pass_and_weak() {
    RunResult run;
    run.info = sample_info();
    CheckResult weak = sample_roundtrip_pass();
    weak.check_name = "chi2";
    weak.case_name = "tiny_light";
    weak.summary = "chi2 990.1 dof 1023 p 0.77; 90% power: tilt 0.31";
    weak.weak = "cannot see a 5% tilt of cos theta (90% power only at a tilt of 0.31)";
    run.results = {sample_roundtrip_pass(), weak};
    return run;
}

TEST(WeakRows, AreNotFailures) {
    RunResult run = pass_and_weak();
    EXPECT_TRUE(run.all_passed());
    EXPECT_EQ(verdict_word(run.results[1]), "weak");
    EXPECT_EQ(verdict_word(run.results[0]), "pass");
    run.results[1].verdict = Verdict::Fail;  // a failed row is a failure, weak or not
    EXPECT_EQ(verdict_word(run.results[1]), "FAIL");
}

TEST(WeakRows, TheTableSaysWeakAndWhatTheRowCouldNotSee) {
    std::ostringstream out;
    print_table(pass_and_weak(), out, TableStyle{});
    EXPECT_THAT(out.str(), HasSubstr("weak   chi2"));
    EXPECT_THAT(out.str(), HasSubstr("passed (1 weak: could not see a 5% tilt)"));
    EXPECT_THAT(out.str(), HasSubstr("chi2 tiny_light: cannot see a 5% tilt of cos theta"));
    EXPECT_THAT(out.str(), Not(HasSubstr("What failed")));
}

TEST(WeakRows, JsonCarriesItAndAgreesWithTheSchema) {
    const auto doc = nlohmann::json::parse(render_json(pass_and_weak()));
    EXPECT_EQ(doc["results"][1]["verdict"], "pass");
    EXPECT_EQ(doc["results"][1]["weak"], "cannot see a 5% tilt of cos theta (90% power only at a tilt of 0.31)");
    EXPECT_EQ(doc["results"][0]["weak"], "");
    const SchemaValidator validator(
        nlohmann::json::parse(read_file(std::string(WARPCHECK_SOURCE_DIR) + "/reports/schema/warpcheck-results.schema.json")));
    EXPECT_THAT(validator.validate(doc), IsEmpty());
}

TEST(WeakRows, TheHtmlBadgeSaysWeak) {
    const std::string html = render_html(pass_and_weak());
    EXPECT_THAT(html, HasSubstr("class=\"badge weak\""));
    EXPECT_THAT(html, HasSubstr(">weak</span>"));
}

}  // namespace
}  // namespace warpcheck
