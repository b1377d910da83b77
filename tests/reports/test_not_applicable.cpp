// A check that does not apply to a case (a round trip of a warp without an
// inverse) is an n/a row in every view: shown with its reason, never a failure
// or an error, and the run still passes.
#include <sstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "reports/render.h"
#include "reports/terminal_table.h"
#include "tests/reports/json_schema_check.h"
#include "tests/reports/sample_run.h"
#include "support/temp_dir.h"
#include "tests/reports/xml_check.h"

namespace warpcheck {
namespace {

using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::Not;
using namespace warpcheck::testing;

RunResult pass_and_not_applicable() {
    RunResult run;
    run.info = sample_info();
    CheckResult na;
    na.case_name = "visible_normals[alpha=0.3]";
    na.check_name = "roundtrip";
    na.verdict = Verdict::NotApplicable;
    na.summary = "not applicable: the warp has no inverse";
    run.results = {sample_roundtrip_pass(), na};
    return run;
}

TEST(NotApplicable, RunStillPasses) {
    RunResult run = pass_and_not_applicable();
    EXPECT_TRUE(run.all_passed());
    run.results[0].verdict = Verdict::Fail;
    EXPECT_FALSE(run.all_passed());
}

TEST(NotApplicable, TerminalTableShowsTheRowButNotAsAFailure) {
    std::ostringstream out;
    print_table(pass_and_not_applicable(), out, TableStyle{});
    EXPECT_THAT(out.str(), HasSubstr("n/a    roundtrip  visible_normals[alpha=0.3]"));
    EXPECT_THAT(out.str(), HasSubstr("not applicable: the warp has no inverse"));
    EXPECT_THAT(out.str(), Not(HasSubstr("What failed")));
    // The checks that ran, as the progress display counts them, and the n/a rows apart.
    EXPECT_THAT(out.str(), HasSubstr("1 checks: 1 passed, 0 failed, 0 errors; 1 n/a, not run in "));
}

TEST(NotApplicable, JsonSaysSoAndAgreesWithTheSchema) {
    const auto doc = nlohmann::json::parse(render_json(pass_and_not_applicable()));
    EXPECT_EQ(doc["results"][1]["verdict"], "not_applicable");
    EXPECT_EQ(doc["totals"]["not_applicable"], 1);
    EXPECT_EQ(doc["totals"]["failed"], 0);
    const SchemaValidator validator(
        nlohmann::json::parse(read_file(std::string(WARPCHECK_SOURCE_DIR) + "/reports/schema/warpcheck-results.schema.json")));
    EXPECT_THAT(validator.validate(doc), IsEmpty());
}

TEST(NotApplicable, JunitMarksTheRowSkipped) {
    const std::string junit = render_junit(pass_and_not_applicable());
    EXPECT_THAT(xml_problem(junit), IsEmpty());
    EXPECT_THAT(junit, HasSubstr("tests=\"2\" failures=\"0\" errors=\"0\" skipped=\"1\""));
    EXPECT_THAT(junit, HasSubstr("<skipped message=\"not applicable: the warp has no inverse\"/>"));
    EXPECT_EQ(count_of(junit, "<failure "), 0u);
    EXPECT_EQ(count_of(junit, "<error "), 0u);
}

TEST(NotApplicable, HtmlShowsAnNaBadgeAndAPassingBanner) {
    const std::string html = render_html(pass_and_not_applicable());
    EXPECT_THAT(xml_problem(html), IsEmpty());
    EXPECT_THAT(html, HasSubstr("<span class=\"badge na\">n/a</span>"));
    EXPECT_THAT(html, HasSubstr("Every check that applies passed (1 of 2); 1 not applicable."));
    EXPECT_THAT(html, Not(HasSubstr("FAILED")));
}

}  // namespace
}  // namespace warpcheck
