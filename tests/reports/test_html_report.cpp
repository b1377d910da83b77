// The HTML report of issue 25: rows grouped by family with failures and the
// weakest first, packed details, the Judged table of each row (its p-value's
// parts and every limit), the limits and deciding points drawn into the
// checks' plots, and the legend of each check's p-value.
#include <cmath>
#include <limits>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "reports/html_report_parts.h"
#include "reports/render.h"
#include "tests/reports/html_unpack.h"
#include "tests/reports/sample_run.h"
#include "support/temp_dir.h"
#include "tests/reports/xml_check.h"

namespace warpcheck {
namespace {

using ::testing::ContainsRegex;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::Not;
using namespace warpcheck::testing;

constexpr double kLevel = 7.28e-05;

CheckResult row(std::string case_name, std::string check, Verdict v) {
    CheckResult r;
    r.case_name = std::move(case_name);
    r.check_name = std::move(check);
    r.verdict = v;
    r.summary = "key figure";
    return r;
}

CheckResult roundtrip_row(std::string case_name, double max_error, Verdict v = Verdict::Pass) {
    CheckResult r = row(std::move(case_name), "roundtrip", v);
    r.figures = {{"max_error", max_error}, {"tolerance", 1e-5}, {"failures", v == Verdict::Pass ? 0.0 : 3.0},
                 {"resolution_limited", 7}};
    // Its judged line with the margin the report reads (validate/checks/judged.h).
    JudgedQuantity error{"largest |invert(sample(u)) \u2212 u|", std::to_string(max_error), "\u2264 1e-05",
                         max_error <= 1e-5 ? JudgedQuantity::State::Within : JudgedQuantity::State::Beyond};
    error.margin_kind = JudgedQuantity::Margin::OfLimit;
    error.margin = max_error / 1e-5;
    r.judged = {error};
    return r;
}

CheckResult p_row(std::string case_name, std::string check, double p) {
    CheckResult r = row(std::move(case_name), std::move(check), Verdict::Pass);
    r.p_value = p;
    r.level = kLevel;
    return r;
}

/// A chi-square row as the chi2 check writes it: Pearson's p and the largest
/// residual's, combined as min(P / 0.8, L / 0.2).
CheckResult chi2_row(double pearson, double local) {
    CheckResult r = p_row("uniform_disk_concentric", "chi2", std::min({1.0, pearson / 0.8, local / 0.2}));
    r.figures = {{"statistic", 968.5709}, {"dof", 1023},         {"p_value", pearson},          {"integral", 0.99999996},
                 {"integral_tolerance", 9.5e-07}, {"cells", 1024}, {"zero_expected_cells", 0}, {"outside", 0},
                 {"local_max_residual", -3.73},   {"local_cell", 713}, {"local_p_value", local}};
    if (!(*r.p_value >= kLevel)) r.verdict = Verdict::Fail;
    Heatmap residual{"residual (obs - exp) / sqrt(exp)", 32, 32, 0.0, 6.283185307179586, 0.0, 1.0, std::vector<double>(1024, 0.5)};
    residual.color_scale = Heatmap::ColorScale::Diverging;
    residual.min_color_limit = 4.0;
    Plot maps;
    maps.kind = Plot::Kind::Heatmaps;
    maps.heatmaps = {Heatmap{"observed", 32, 32, 0.0, 6.283185307179586, 0.0, 1.0, std::vector<double>(1024, 976.0)}, residual};
    r.plots = {maps};
    return r;
}

/// An unbinned row: Kuiper judges phi, Anderson-Darling cos theta.
CheckResult unbinned_row() { return sample_unbinned_pass(kLevel); }

// ---- order ------------------------------------------------------------------

RunResult families_run() {
    RunResult run;
    run.info = sample_info();
    run.results = {roundtrip_row("a[x=1]", 1e-7),                       // 0: 0.01 of tol
                   p_row("a[x=1]", "chi2", 0.5),                        // 1: 6868x level
                   roundtrip_row("a[x=2]", 9e-6),                       // 2: 0.9 of tol, a's weakest
                   p_row("b[y=1]", "chi2", 0.5),                        // 3
                   roundtrip_row("b[y=1]", 2e-5, Verdict::Fail),        // 4: b's failure
                   row("c", "consistency", Verdict::Error),             // 5: an error
                   row("a[x=3]", "roundtrip", Verdict::NotApplicable)};  // 6
    return run;
}

TEST(HtmlReport, FamiliesWithFailuresComeFirstThenRowsByHowCloseToTheirLimit) {
    const RunResult run = families_run();
    const auto groups = html::family_groups(run);
    ASSERT_EQ(groups.size(), 3u);
    EXPECT_EQ(groups[0].family, "b");
    EXPECT_THAT(groups[0].rows, ElementsAre(4, 3));
    EXPECT_EQ(groups[1].family, "c");
    EXPECT_EQ(groups[2].family, "a");
    EXPECT_THAT(groups[2].rows, ElementsAre(2, 0, 1, 6));  // 0.9 of tol, 0.01 of tol, 6868x level, n/a
    // The page lists them in that order, each family under its heading.
    const std::string html = render_html(run);
    std::vector<std::size_t> at;
    for (int i : {4, 3, 5, 2, 0, 1, 6}) at.push_back(html.find(fmt::format("id=\"r-{}\"", i)));
    EXPECT_TRUE(std::is_sorted(at.begin(), at.end())) << "rows out of order";
    EXPECT_LT(html.find("data-f=\"b\""), html.find("data-f=\"a\""));
    EXPECT_THAT(html, HasSubstr("<span class=\"fc\">1 case \u00b7 2 checks \u00b7 <span class=\"bad\">1 failed</span></span>"));
}

TEST(HtmlReport, MarginColumnReadsAsTheTerminalsWithAGauge) {
    RunResult run = families_run();
    run.results[3].p_value = 13 * kLevel;
    const std::string html = render_html(run);
    EXPECT_THAT(html, ContainsRegex("<i style=\"width:6[0-9]%\"></i></span>13x level</span>"));  // 1/13 of the way, on a log scale
    EXPECT_THAT(html, ContainsRegex("gauge near\"><i style=\"width:98%\"></i></span>0.9 of tol"));
    // The failed round trip failed on its tolerance: its margin shows, past the limit.
    EXPECT_THAT(html, HasSubstr("gauge over\"><i style=\"width:100%\"></i></span>2 of tol"));
}

TEST(HtmlReport, OpenRowsAreTheFailuresAndTheRestArePacked) {
    const RunResult run = families_run();
    const std::string html = render_html(run);
    EXPECT_THAT(xml_problem(html), IsEmpty());
    EXPECT_THAT(html, ContainsRegex("id=\"r-4\"[^>]* open=\"open\">"));
    EXPECT_THAT(html, ContainsRegex("id=\"r-5\"[^>]* open=\"open\">"));
    for (int i : {0, 1, 2, 3, 6}) EXPECT_THAT(html, ContainsRegex(fmt::format("id=\"r-{}\"[^>]* data-p=\"[0-9]+\">", i)));
    // One pack per check of the packed rows, each holding its rows' details.
    const auto packs = report_packs(html);
    ASSERT_EQ(packs.size(), 2u);  // roundtrip (0, 2, 6), chi2 (1, 3)
    std::set<std::string> rows;
    for (const auto& [id, bodies] : packs)
        for (const auto& [index, body] : bodies.items()) {
            rows.insert(index);
            EXPECT_THAT(body.get<std::string>(), HasSubstr("class=\"facts\""));
        }
    EXPECT_THAT(rows, ElementsAre("0", "1", "2", "3", "6"));
    const std::string opened = unpacked_html(html);
    EXPECT_THAT(xml_problem(opened), IsEmpty());
    EXPECT_THAT(opened, HasSubstr("<dt>resolution_limited</dt>"));
}

TEST(HtmlReport, ARunOfManyFailuresOpensOnlyTheFirstTwenty) {
    RunResult run;
    run.info = sample_info();
    for (int i = 0; i < 50; ++i) run.results.push_back(sample_chi2_fail(8, 16));
    const std::string html = render_html(run);
    EXPECT_EQ(count_of(html, "open=\"open\""), 20u);
    EXPECT_EQ(count_of(html, " data-p=\""), 30u);
    EXPECT_THAT(html, HasSubstr("The first 20 are open below; the others open with a click."));
    // Thirty packed failures of the same shape compress: together they take less room than two open ones.
    const std::size_t packed = html.size() - html.find("<script type=\"application/x-warpcheck-pack\"");
    const std::size_t first_open = html.find("id=\"r-1\"") - html.find("id=\"r-0\"");
    EXPECT_LT(packed, 2 * first_open);
    EXPECT_THAT(xml_problem(unpacked_html(html)), IsEmpty());
}

TEST(HtmlReport, TheSearchReadsTheMessageOfRowsThatAreNotOpen) {
    RunResult run = families_run();
    run.results[0].message = "bias reported: 12 floats never produced";
    const std::string html = render_html(run);
    EXPECT_THAT(html, ContainsRegex("id=\"r-0\"[^>]* data-s=\"bias reported: 12 floats never produced\""));
    EXPECT_THAT(html, HasSubstr("id=\"q\""));
    EXPECT_THAT(html, HasSubstr("id=\"f-check\""));
    EXPECT_THAT(html, HasSubstr("<option value=\"b\">b</option>"));  // a family to filter by
    EXPECT_THAT(html, HasSubstr("data-verdict=\"fail\" aria-pressed=\"false\">failed 1</button>"));
}

// ---- the Judged table (the lines are the checks': tests/validate/checks/test_judged.cpp) ----

TEST(HtmlReport, EveryRowHasItsJudgedTableAndTheLegendExplainsEachPValue) {
    RunResult run;
    run.info = sample_info();
    // The legends as the checks state them (Check::legend), carried by the run.
    run.info.legends = {{"chi2", "Pearson's X\u00b2 of the samples over cells.",
                         "min(p_X\u00b2 / 0.8, p_cell / 0.2), weighted Bonferroni. The summary's p is Pearson's alone."},
                        {"unbinned", "The empirical CDF of each marginal against the CDF of the pdf.",
                         "1 \u2212 (1 \u2212 min p)^k, \u0160id\u00e1k over the k judged tests."},
                        {"roundtrip", "|invert(sample(u)) \u2212 u| against the case's tolerance.", ""}};
    run.results = {chi2_row(1e-9, 0.5), unbinned_row(), roundtrip_row("a", 1e-7)};
    using State = JudgedQuantity::State;
    run.results[0].judged = {{"Pearson X\u00b2 = 968.6 on 1023 dof: p-value", "1.00e-09", "\u2265 5.82e-05", State::Beyond},
                             {"cells pooled", "3", "counted", State::Reported}};
    run.results[1].judged = {{"p-value", "0.0199", "\u2265 7.28e-05", State::Within}};
    run.results[2].judged.clear();
    const std::string html = unpacked_html(render_html(run));
    // A table for each row with lines, drawn as the check wrote them; none for the row without.
    EXPECT_EQ(count_of(html, "<table class=\"judged\">"), 2u);
    EXPECT_THAT(html, ContainsRegex("<tr class=\"beyond\"><td>Pearson X\u00b2 = 968.6 on 1023 dof: p-value</td><td class=\"val\">1.00e-09</td>"));
    EXPECT_THAT(html, HasSubstr("<tr class=\"reported\"><td>cells pooled</td>"));
    EXPECT_THAT(html, HasSubstr("min(p_X\u00b2 / 0.8, p_cell / 0.2)"));
    EXPECT_THAT(html, HasSubstr("The summary&#39;s p is Pearson&#39;s alone."));
    EXPECT_THAT(html, HasSubstr("1 \u2212 (1 \u2212 min p)^k, \u0160id\u00e1k over the k judged tests"));
    EXPECT_THAT(xml_problem(html), IsEmpty());
}

// The report names no check: a check it has never heard of (a renderer's own)
// is explained by the legend its run carries, and a row whose run carries
// none (a file written before legends travelled with runs) shows an empty one.
TEST(HtmlReport, EachChecksLegendIsTheOneItsRunCarriesWhateverTheCheck) {
    RunResult run;
    run.info = sample_info();
    CheckResult mine = roundtrip_row("a", 1e-7);
    mine.check_name = "my_renderers_check";
    CheckResult old = roundtrip_row("b", 1e-7);
    old.check_name = "a_check_without_legend";
    run.results = {mine, old};
    run.info.legends = {{"my_renderers_check", "Whether my sampler's caustic paths agree, in my words.",
                         "Fisher's method over the paths."}};
    const std::string html = unpacked_html(render_html(run));
    EXPECT_THAT(html, HasSubstr("<td class=\"what\">Whether my sampler&#39;s caustic paths agree, in my words.</td>"
                                "<td class=\"what\">Fisher&#39;s method over the paths.</td>"));
    EXPECT_THAT(html, HasSubstr("a_check_without_legend</td><td class=\"n\">1</td><td class=\"n\">0</td><td "
                                "class=\"n\">0</td><td class=\"n\">0</td><td class=\"what\"></td><td "
                                "class=\"what\">\u2014</td>"));
    EXPECT_THAT(xml_problem(html), IsEmpty());
}

// ---- what the plots show ----------------------------------------------------------
// The marks are the checks' (tests/validate/checks/test_plot_marks.cpp); the
// report draws a plot's own marks and note whatever check wrote them.

TEST(HtmlReport, APlotsOwnMarksAndNoteAreDrawnWhateverTheCheck) {
    RunResult run;
    run.info = sample_info();
    CheckResult r = chi2_row(0.887, 0.144);
    r.check_name = "my_renderers_check";
    Plot& maps = r.plots[0];
    maps.cells = {{1, 713 / 32, 713 % 32, "my worst cell"}};
    maps.scale_marks = {{1, 5.67, "my limit"}};
    maps.note = "What my check judges in this map.";
    Plot curve;
    curve.kind = Plot::Kind::Points;
    curve.series = {{"residual", {0.0, 1.0, 2.0}, {0.5, -1.0, 2.0}}};
    curve.limits = {{false, 3.0, "my bound"}};
    curve.highlights = {{2.0, 2.0, "my point"}};
    r.plots.push_back(curve);
    run.results = {r};
    const std::string html = unpacked_html(render_html(run));
    for (const char* label : {">my worst cell</text>", "my limit", ">my bound</text>", ">my point</text>"})
        EXPECT_THAT(html, HasSubstr(label)) << label;
    EXPECT_THAT(html, HasSubstr("<p class=\"note\">What my check judges in this map.</p>"));
    EXPECT_EQ(count_of(html, "What my check judges"), 1u);
    EXPECT_THAT(xml_problem(html), IsEmpty());
}

// The scale and the axes widen to show a plot's marks, as they do for the
// caller's (SvgOptions): a limit beyond every value is drawn inside the frame.
TEST(HtmlReport, APlotsMarksWidenItsAxesAndScale) {
    CheckResult r = sample_roundtrip_pass();  // errors 1e-12 .. 1e-7 by decade
    r.plots[0].log_x = false;
    r.plots[0].series[0].x = {-12, -11, -10, -9, -8, -7};
    r.plots[0].limits = {{true, -3.5, "tolerance 0.001"}};
    const std::string svg = render_svg(r.plots[0]);
    EXPECT_THAT(svg, HasSubstr(">tolerance 0.001</text>"));
    const std::smatch line = [&] {
        std::smatch m;
        std::regex_search(svg, m, std::regex("<path d=\"M([0-9.]+) [0-9.]+V[0-9.]+\" stroke=\"#c62828\""));
        return m;
    }();
    ASSERT_FALSE(line.empty());
    EXPECT_LT(std::stod(line[1]), 560.0 - 16.0);
    const CheckResult chi2 = [] {
        CheckResult c = chi2_row(0.887, 0.144);
        c.plots[0].scale_marks = {{1, 5.6707, "|r| = 5.7: one cell alone fails"}};
        return c;
    }();
    EXPECT_EQ(count_of(render_svg(chi2.plots[0]), "v16\" stroke=\"#c62828\""), 2u);  // at -5.67 and +5.67
}

}  // namespace
}  // namespace warpcheck
