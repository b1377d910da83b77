// The three report files of a run with one passing and one failing result:
// each holds both results with their figures; the HTML and JUnit are
// well-formed, the JSON agrees with its schema.
#include <cstdlib>
#include <regex>
#include <set>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "reports/outputs.h"
#include "reports/render.h"
#include "tests/reports/html_unpack.h"
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

bool have_xmllint() { return std::system("xmllint --version > /dev/null 2>&1") == 0; }

nlohmann::json load_schema() {
    return nlohmann::json::parse(read_file(std::string(WARPCHECK_SOURCE_DIR) + "/reports/schema/warpcheck-results.schema.json"));
}

class ReportFiles : public ::testing::Test {
protected:
    void SetUp() override {
        run = sample_pass_and_fail();
        write_html_report(run, dir.file("report.html"));
        write_json_report(run, dir.file("results.json"));
        write_junit_report(run, dir.file("junit.xml"));
        html = read_file(dir.file("report.html"));
        opened = unpacked_html(html);
        json = read_file(dir.file("results.json"));
        junit = read_file(dir.file("junit.xml"));
    }
    TempDir dir;
    RunResult run;
    std::string html, opened, json, junit;  ///< opened: html with every packed row's details unpacked
};

TEST_F(ReportFiles, HtmlShowsBothResultsWithTheirFigures) {
    EXPECT_THAT(html, HasSubstr("uniform_cone[cos_theta_max=0.3]"));
    EXPECT_THAT(html, HasSubstr("trowbridge_reitz_visible[ax=0.3,ay=0.15,theta_o=60]"));
    for (const auto& r : run.results)
        for (const auto& f : r.figures) EXPECT_THAT(opened, HasSubstr("<dt>" + f.name + "</dt>")) << r.case_name;
    EXPECT_THAT(opened, HasSubstr("1452.3"));     // chi2 statistic
    EXPECT_THAT(opened, HasSubstr("5.96e-08"));   // round-trip max error
    EXPECT_THAT(html, HasSubstr(run.results[1].message));
    EXPECT_THAT(opened, HasSubstr("Worst inputs"));
    // Summary: counts, seed, samples, both levels with the number of tests, time, machine, compiler.
    EXPECT_THAT(html, HasSubstr("7.18e-05"));
    EXPECT_THAT(html, HasSubstr("140 statistical tests"));
    EXPECT_THAT(html, HasSubstr("GCC 12.2.0"));
    EXPECT_THAT(html, HasSubstr("x86_64 Linux"));
    EXPECT_THAT(html, HasSubstr("14.2 s"));
}

TEST_F(ReportFiles, HtmlHasTheFigures) {
    // The failing chi2 has 3 heatmaps (one shared sequential scale, one diverging
    // scale) and a bar plot; the round trip a bar plot, packed until opened.
    EXPECT_EQ(count_of(opened, "<svg "), 3u);
    EXPECT_EQ(count_of(html, "<svg "), 2u);
    EXPECT_EQ(count_of(opened, "<image "), 3u);
    EXPECT_EQ(count_of(opened, "data:image/png;base64,"), 3u);
    EXPECT_EQ(count_of(opened, "<linearGradient "), 2u);
    EXPECT_THAT(opened, HasSubstr("Observed and expected counts per cell"));
    EXPECT_THAT(opened, HasSubstr("no value (e.g. pooled)"));  // NaN residuals are hatched and explained
    EXPECT_THAT(opened, HasSubstr(">cos theta</tspan>"));       // axes in the domain's coordinates
    EXPECT_THAT(opened, HasSubstr(">2\xCF\x80</text>"));       // phi ticks in multiples of pi
}

TEST_F(ReportFiles, HtmlPutsTheFailureFirstAndLinksEveryRowToItsDetails) {
    const auto results = html.find("<section id=\"results\">");
    ASSERT_NE(results, std::string::npos);
    EXPECT_LT(html.find("id=\"r-1\"", results), html.find("id=\"r-0\"", results));
    std::set<std::string> ids;
    const std::regex id_re("id=\"([^\"]+)\"");
    for (auto it = std::sregex_iterator(opened.begin(), opened.end(), id_re); it != std::sregex_iterator(); ++it)
        EXPECT_TRUE(ids.insert((*it)[1]).second) << "duplicate id " << (*it)[1];
    const std::regex href_re("href=\"#([^\"]+)\"");
    int links = 0;
    for (auto it = std::sregex_iterator(opened.begin(), opened.end(), href_re); it != std::sregex_iterator(); ++it, ++links)
        EXPECT_TRUE(ids.count((*it)[1])) << "link to a missing anchor " << (*it)[1];
    EXPECT_GE(links, 1);  // the passing round trip is among the closest to their limits
    // The failure is open with its details inline; the pass is a click away, its details packed.
    EXPECT_THAT(html, ::testing::ContainsRegex("<details class=\"r fail\" id=\"r-1\"[^>]* open=\"open\">"));
    EXPECT_THAT(html, ::testing::ContainsRegex("<details class=\"r pass\" id=\"r-0\"[^>]* data-p=\"0\">"));
    EXPECT_THAT(html, HasSubstr("--check chi2 --seed 1</code></pre>"));  // the failure's rerun command, inline
}

TEST_F(ReportFiles, HtmlIsSelfContainedAndWellFormed) {
    EXPECT_THAT(xml_problem(html), IsEmpty());
    EXPECT_THAT(xml_problem(opened), IsEmpty());
    // Nothing is fetched: no src or href to anything but an anchor or a data URL,
    // no CSS imports or URLs (the SVG namespace is a name, not a fetch).
    EXPECT_THAT(html, Not(HasSubstr("src=")));
    EXPECT_THAT(html, Not(HasSubstr("@import")));
    const std::regex href_re("href=\"([^\"]*)\"");
    for (auto it = std::sregex_iterator(opened.begin(), opened.end(), href_re); it != std::sregex_iterator(); ++it) {
        const std::string target = (*it)[1];
        EXPECT_TRUE(target.rfind("#", 0) == 0 || target.rfind("data:image/png;base64,", 0) == 0) << target.substr(0, 80);
    }
    const std::regex url_re("url\\(([^)]*)\\)");
    for (auto it = std::sregex_iterator(opened.begin(), opened.end(), url_re); it != std::sregex_iterator(); ++it)
        EXPECT_EQ(std::string((*it)[1]).rfind("#", 0), 0u) << (*it)[0];
    if (have_xmllint()) {
        EXPECT_EQ(std::system(("xmllint --noout " + dir.file("report.html")).c_str()), 0);
    }
}

TEST_F(ReportFiles, JsonHasBothResultsAndAgreesWithTheSchema) {
    const auto doc = nlohmann::json::parse(json);
    EXPECT_EQ(doc["schema_version"], kJsonSchemaVersion);
    ASSERT_EQ(doc["results"].size(), 2u);
    EXPECT_EQ(doc["results"][0]["case"], "uniform_cone[cos_theta_max=0.3]");
    EXPECT_EQ(doc["results"][0]["verdict"], "pass");
    EXPECT_EQ(doc["results"][1]["verdict"], "fail");
    EXPECT_DOUBLE_EQ(doc["results"][1]["figures"]["statistic"].get<double>(), 1452.3);
    EXPECT_DOUBLE_EQ(doc["results"][0]["figures"]["max_error"].get<double>(), 5.96e-08);
    EXPECT_DOUBLE_EQ(doc["results"][1]["p_value"].get<double>(), 3.1e-12);
    EXPECT_TRUE(doc["results"][0]["p_value"].is_null());
    const auto& maps = doc["results"][1]["plots"][0];
    EXPECT_EQ(maps["kind"], "heatmaps");
    ASSERT_EQ(maps["heatmaps"].size(), 3u);
    EXPECT_EQ(maps["heatmaps"][0]["values"].size(), 16u * 32u);
    EXPECT_EQ(maps["heatmaps"][2]["color_scale"], "diverging");
    EXPECT_EQ(doc["results"][0]["tables"][0]["rows"].size(), 2u);
    EXPECT_EQ(doc["totals"]["failed"], 1);
    EXPECT_EQ(doc["results"][0]["stream"]["seed"].get<std::uint64_t>(), 0x853c49e6748fea9bULL);

    const SchemaValidator validator(load_schema());
    EXPECT_THAT(validator.validate(doc), IsEmpty());
}

TEST(JsonSchema, TheValidatorRejectsWhatTheSchemaForbids) {
    // The schema test is worth something only if it can fail.
    const SchemaValidator validator(load_schema());
    const auto good = nlohmann::json::parse(render_json(sample_pass_and_fail()));
    ASSERT_THAT(validator.validate(good), IsEmpty());
    auto missing = good;
    missing["results"][1].erase("verdict");
    EXPECT_THAT(validator.validate(missing), Not(IsEmpty()));
    auto wrong_enum = good;
    wrong_enum["results"][0]["verdict"] = "PASS";
    EXPECT_THAT(validator.validate(wrong_enum), Not(IsEmpty()));
    auto extra = good;
    extra["results"][0]["undocumented"] = 1;
    EXPECT_THAT(validator.validate(extra), Not(IsEmpty()));
    auto bad_number = good;
    bad_number["results"][0]["figures"]["max_error"] = "nan";
    EXPECT_THAT(validator.validate(bad_number), Not(IsEmpty()));
    auto old_version = good;
    old_version["schema_version"] = 0;
    EXPECT_THAT(validator.validate(old_version), Not(IsEmpty()));
    // The checks' legends, carried by the run (RunInfo::legends).
    RunResult with_legends = sample_pass_and_fail();
    with_legends.info.legends = {{"roundtrip", "what it judges", ""}, {"chi2", "what it judges", "how p is formed"}};
    const auto legends = nlohmann::json::parse(render_json(with_legends));
    ASSERT_EQ(legends["run"]["legends"]["checks"].size(), 2u);
    EXPECT_EQ(legends["run"]["legends"]["checks"][1]["p_value"], "how p is formed");
    EXPECT_THAT(validator.validate(legends), IsEmpty());
    auto extra_legend = legends;
    extra_legend["run"]["legends"]["checks"][0]["colour"] = "red";
    EXPECT_THAT(validator.validate(extra_legend), Not(IsEmpty()));
    EXPECT_FALSE(good["run"].contains("legends")) << "a run without legends writes none";
}

TEST(JsonReport, NonFiniteNumbersAndHostileTextSurvive) {
    RunResult run = sample_everything();
    run.results.back().message += std::string("\xff\xfe bad utf-8");
    const auto doc = nlohmann::json::parse(render_json(run));
    const auto& error = doc["results"][4];
    EXPECT_EQ(error["verdict"], "error");
    EXPECT_EQ(error["figures"]["nan_figure"], "NaN");
    EXPECT_EQ(error["figures"]["inf_figure"], "Infinity");
    EXPECT_EQ(error["p_value"], "NaN");
    EXPECT_EQ(error["case"], "evil<case>&[a=1,b=\"2\",c='3']");
    EXPECT_THAT(error["message"].get<std::string>(), HasSubstr("\xEF\xBF\xBD"));
    EXPECT_THAT(SchemaValidator(load_schema()).validate(doc), IsEmpty());
}

TEST_F(ReportFiles, JunitHasOneTestcasePerRowAndParses) {
    EXPECT_THAT(xml_problem(junit), IsEmpty());
    EXPECT_EQ(count_of(junit, "<testcase "), 2u);
    EXPECT_EQ(count_of(junit, "<failure "), 1u);
    EXPECT_EQ(count_of(junit, "<error "), 0u);
    EXPECT_THAT(junit, HasSubstr("<testsuites name=\"warpcheck\" tests=\"2\" failures=\"1\" errors=\"0\""));
    EXPECT_THAT(junit, HasSubstr("name=\"uniform_cone[cos_theta_max=0.3]\" classname=\"warpcheck.roundtrip\""));
    EXPECT_THAT(junit, HasSubstr("name=\"trowbridge_reitz_visible[ax=0.3,ay=0.15,theta_o=60]\" classname=\"warpcheck.chi2\""));
    EXPECT_THAT(junit, HasSubstr("statistic: 1452.3"));
    EXPECT_THAT(junit, HasSubstr("rerun: validate --case &#39;trowbridge_reitz_visible"));
    if (have_xmllint()) {
        EXPECT_EQ(std::system(("xmllint --noout " + dir.file("junit.xml")).c_str()), 0);
    }
}

TEST(HostileText, IsEscapedInHtmlAndJunit) {
    RunResult run = sample_everything();
    run.results.back().message += std::string("\x01\xff control and bad bytes");
    const std::string html = unpacked_html(render_html(run));
    const std::string junit = render_junit(run);
    EXPECT_THAT(xml_problem(html), IsEmpty());
    EXPECT_THAT(xml_problem(junit), IsEmpty());
    EXPECT_THAT(html, Not(HasSubstr("<script>alert")));
    EXPECT_THAT(html, HasSubstr("evil&lt;case&gt;&amp;[a=1,b=&quot;2&quot;,c=&#39;3&#39;]"));
    EXPECT_THAT(junit, HasSubstr("<error message=\"sample() threw"));
    EXPECT_EQ(count_of(junit, "<testsuite "), 5u);  // one per check
}

TEST(HtmlReport, ShowsWhereACheckSpentItsTime) {
    RunResult run = sample_everything();
    run.results.front().phases = {{"integration", 0.25}, {"sampling+binning", 1.5}};
    const std::string html = unpacked_html(render_html(run));
    EXPECT_THAT(html, HasSubstr("integration <b>"));
    EXPECT_THAT(html, HasSubstr("sampling+binning <b>"));
    EXPECT_THAT(xml_problem(html), IsEmpty());
}

TEST(EmptyRun, StillMakesValidReports) {
    RunResult run;
    run.info = sample_info();
    EXPECT_THAT(xml_problem(render_html(run)), IsEmpty());
    EXPECT_THAT(xml_problem(render_junit(run)), IsEmpty());
    EXPECT_THAT(SchemaValidator(load_schema()).validate(nlohmann::json::parse(render_json(run))), IsEmpty());
}

TEST(ReportWriters, UnwritablePathIsAReportError) {
    const RunResult run = sample_pass_and_fail();
    for (auto write : {&write_html_report, &write_json_report, &write_junit_report}) {
        try {
            write(run, "/nonexistent-folder/report.out");
            ADD_FAILURE() << "no error";
        } catch (const ReportError& e) {
            EXPECT_THAT(e.what(), HasSubstr("cannot write /nonexistent-folder/report.out: No such file or directory"));
        }
    }
}

// Writes the full sample report where WARPCHECK_SAMPLE_REPORT says, for the
// headless-browser check (tests/reports/render_check.sh); skipped otherwise.
TEST(SampleReport, WritesForRendering) {
    const char* path = std::getenv("WARPCHECK_SAMPLE_REPORT");
    if (!path || !*path) GTEST_SKIP() << "WARPCHECK_SAMPLE_REPORT is not set";
    RunResult run = sample_everything();
    for (CheckResult& r : sample_bsdf_family()) run.results.push_back(std::move(r));
    write_html_report(run, path);
}

}  // namespace
}  // namespace warpcheck
