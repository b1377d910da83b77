// Plots across the cases of a family (issue 23: a BSDF's albedo against
// theta_o over its grid): the rows' FamilyPoints gathered into curves per
// value and group, sorted in x, with error bars and limits; the same after a
// trip through JSON (what --merge reads); shown above the family's rows in the
// HTML report; error bars in the SVG; the BSDF checks' judged lines.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "reports/family_plots.h"
#include "reports/html_report_parts.h"
#include "reports/json_input.h"
#include "reports/render.h"
#include "reports/svg_plot.h"
#include "tests/reports/html_unpack.h"
#include "tests/reports/sample_run.h"
#include "support/temp_dir.h"
#include "tests/reports/xml_check.h"

namespace warpcheck {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::Not;
using namespace warpcheck::testing;

const Series* series_labelled(const Plot& plot, const std::string& label) {
    for (const Series& s : plot.series)
        if (s.label == label) return &s;
    return nullptr;
}

// A transmitting BSDF in radiance transport: its albedo (radiance) reaches
// 2.1 across the interface, and only its energy albedo is bounded by 1. The
// bound is drawn against the energy albedo, in a plot of its own, never
// against the radiance albedo it does not apply to.
TEST(FamilyPlots, ABoundIsDrawnAgainstTheQuantityItBounds) {
    std::vector<CheckResult> rows;
    for (const double theta_o : {0.0, 60.0}) {
        CheckResult r = sample_bsdf_albedo(0.3, theta_o, 2.1, 2.1, 1e-3);
        r.case_name = "rough_dielectric[alpha=0.3,theta_o=" + std::to_string(int(theta_o)) + "]";
        for (FamilyPoint& p : r.family_points) p.family = "rough_dielectric";
        r.family_points[0].values.push_back({"energy albedo", 0.93});
        rows.push_back(std::move(r));
    }
    const std::vector<FamilyPlot> plots = family_plots(rows);
    ASSERT_EQ(plots.size(), 3u);
    EXPECT_EQ(plots[0].plot.title, "albedo against theta_o");
    EXPECT_TRUE(plots[0].limits.empty()) << "the radiance albedo is not judged against the energy bound";
    EXPECT_TRUE(series_labelled(plots[0].plot, "albedo, alpha=0.3"));
    EXPECT_FALSE(series_labelled(plots[0].plot, "energy albedo, alpha=0.3"));
    EXPECT_EQ(plots[1].plot.title, "energy albedo against theta_o");
    ASSERT_EQ(plots[1].limits.size(), 1u);
    EXPECT_EQ(plots[1].limits[0].name, "energy bound");
    ASSERT_EQ(plots[1].plot.series.size(), 1u);
    EXPECT_EQ(plots[1].plot.series[0].label, "energy albedo, alpha=0.3");
    EXPECT_EQ(plots[2].plot.title, "mean weight minus albedo against theta_o");
    // A reflecting BSDF's albedo is its energy albedo: one plot, under the bound.
    const std::vector<FamilyPlot> reflecting = family_plots(sample_bsdf_family());
    ASSERT_EQ(reflecting.size(), 2u);
    ASSERT_EQ(reflecting[0].limits.size(), 1u);
    EXPECT_EQ(reflecting[0].limits[0].name, "energy bound");
}

TEST(FamilyPlots, GatherTheRowsPointsIntoCurvesPerValueAndGroupInOrderOfX) {
    const std::vector<FamilyPlot> plots = family_plots(sample_bsdf_family());
    ASSERT_EQ(plots.size(), 2u);
    EXPECT_EQ(plots[0].family, "rough_conductor");
    EXPECT_EQ(plots[0].plot.title, "albedo against theta_o");
    EXPECT_EQ(plots[1].plot.title, "mean weight minus albedo against theta_o");
    EXPECT_EQ(plots[0].plot.x_label, "theta_o (degrees)");
    ASSERT_EQ(plots[0].plot.series.size(), 4u);  // two values by two roughnesses
    const Series* mean = series_labelled(plots[0].plot, "mean weight (99% interval), alpha=0.3");
    ASSERT_TRUE(mean);
    EXPECT_THAT(mean->x, ElementsAre(0, 60, 85));  // the rows list 60, 0, 85
    EXPECT_THAT(mean->y, ElementsAre(0.8099, 0.7567, 0.8314));
    ASSERT_EQ(mean->y_low.size(), 3u);
    EXPECT_NEAR(mean->y_high[0] - mean->y_low[0], 2 * 2.576 * 2.4e-4, 1e-15);
    const Series* albedo = series_labelled(plots[0].plot, "albedo, alpha=0.05");
    ASSERT_TRUE(albedo);
    EXPECT_THAT(albedo->y, ElementsAre(0.921, 0.912, 0.858));
    EXPECT_THAT(albedo->y_low, IsEmpty());  // no value of the curve has an interval
    // Six rows give the bound once.
    ASSERT_EQ(plots[0].limits.size(), 1u);
    EXPECT_EQ(plots[0].limits[0].name, "energy bound");
    EXPECT_EQ(plots[0].limits[0].value, 1.0);
}

TEST(FamilyPlots, AValueWithoutAnIntervalHasNoErrorBarBesideOnesThatHave) {
    std::vector<CheckResult> rows = sample_bsdf_family();
    FamilyValue& first = rows[0].family_points[0].values[0];
    first.low = 1.0, first.high = 0.0;  // low > high: no interval
    const std::vector<FamilyPlot> plots = family_plots(rows);
    const Series* mean = series_labelled(plots[0].plot, "mean weight (99% interval), alpha=0.3");
    ASSERT_TRUE(mean);
    ASSERT_EQ(mean->y_low.size(), 3u);
    EXPECT_TRUE(std::isnan(mean->y_low[1]));  // theta_o 60, the first row
    EXPECT_FALSE(std::isnan(mean->y_low[0]));
}

TEST(FamilyPlots, RowsWithoutPointsGiveNone) { EXPECT_THAT(family_plots(sample_everything().results), IsEmpty()); }

// --merge reads the shards' rows from JSON and plots them like the whole run.
TEST(FamilyPlots, TheSameAfterATripThroughJson) {
    RunResult run = sample_pass_and_fail();
    for (CheckResult& r : sample_bsdf_family()) run.results.push_back(std::move(r));
    const RunResult back = parse_json_results(render_json(run));
    const std::vector<FamilyPlot> a = family_plots(run.results), b = family_plots(back.results);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(render_svg(a[i].plot), render_svg(b[i].plot));
}

TEST(HtmlReport, AFamilysPlotsAcrossItsCasesStandAboveItsRows) {
    RunResult run = sample_pass_and_fail();
    for (CheckResult& r : sample_bsdf_family()) run.results.push_back(std::move(r));
    const std::string html = unpacked_html(render_html(run));
    EXPECT_THAT(xml_problem(html), IsEmpty());
    const std::size_t section = html.find("<section class=\"fam\" data-f=\"rough_conductor\">");
    const std::size_t across = html.find("<details class=\"across\" open=\"open\"><summary>Across the family: albedo "
                                         "against theta_o; mean weight minus albedo against theta_o</summary>");
    const std::size_t first_row = html.find("<details class=\"r", section);
    ASSERT_NE(section, std::string::npos);
    ASSERT_NE(across, std::string::npos);
    EXPECT_LT(section, across);
    EXPECT_LT(across, first_row);
    EXPECT_THAT(html, HasSubstr(">energy bound 1</text>"));  // the limit, drawn as the report draws limits
    EXPECT_EQ(count_of(html, "<details class=\"across\""), 1u);  // the other families have no points
}

TEST(SvgPlot, ErrorBarsAreDrawnWithCapsAndWidenTheAxis) {
    Plot p;
    p.kind = Plot::Kind::Lines;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    p.series = {{"mean", {0, 60, 85}, {0.5, 0.5, 0.5}, {0.4, nan, 0.45}, {0.9, nan, 0.55}}};
    const std::string svg = render_svg(p);
    EXPECT_THAT(xml_problem(svg), IsEmpty());
    EXPECT_EQ(count_of(svg, "h6"), 4u);  // two bars, each capped at both ends; none for the NaN interval
    EXPECT_THAT(svg, HasSubstr(">0.9</text>"));  // the axis takes the bar's top in
    EXPECT_THAT(svg, Not(HasSubstr("nan")));
    p.log_y = true;
    p.series[0].y_low[0] = -1.0;  // a low end the log axis cannot show: the bar runs to the axis' end, capless
    EXPECT_EQ(count_of(render_svg(p), "h6"), 3u);
}

}  // namespace
}  // namespace warpcheck
