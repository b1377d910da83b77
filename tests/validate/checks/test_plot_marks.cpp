// The marks a check writes into its plots (JudgedRules::marks, Plot::limits,
// highlights, cells, scale_marks, note), once the run's level is settled:
// each check's rule for what its plots show, with the check (issue 35). The
// report draws them whatever the check (tests/reports/test_html_report.cpp).
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "reports/svg_plot.h"
#include "tests/reports/sample_run.h"
#include "validate/api/registry.h"
#include "validate/checks/check.h"
#include "validate/checks/judged.h"

namespace warpcheck {
namespace {

using ::testing::HasSubstr;
using ::testing::IsEmpty;

constexpr double kLevel = 7.28e-05;

std::size_t count_of(const std::string& text, const std::string& part) {
    std::size_t n = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
    return n;
}

/// The row marked by the rules of the built-in check it names.
CheckResult marked(CheckResult r) {
    Registry registry;
    register_builtin_checks(registry);
    record_judgement(r, registry.find_check(r.check_name)->judged_rules());
    return r;
}

CheckResult p_row(std::string check, double p) {
    CheckResult r;
    r.case_name = "a_case";
    r.check_name = std::move(check);
    r.verdict = p >= kLevel ? Verdict::Pass : Verdict::Fail;
    r.p_value = p;
    r.level = kLevel;
    return r;
}

/// A chi-square row as the chi2 check writes it, with its observed and
/// residual maps: Pearson's p and the largest residual's, min(P / 0.8, L / 0.2).
CheckResult chi2_row(double pearson, double local) {
    CheckResult r = p_row("chi2", std::min({1.0, pearson / 0.8, local / 0.2}));
    r.figures = {{"statistic", 968.5709}, {"dof", 1023},         {"p_value", pearson},          {"integral", 0.99999996},
                 {"integral_tolerance", 9.5e-07}, {"cells", 1024}, {"zero_expected_cells", 0}, {"outside", 0},
                 {"local_max_residual", -3.73},   {"local_cell", 713}, {"local_p_value", local}};
    Heatmap residual{"residual (obs - exp) / sqrt(exp)", 32, 32, 0.0, 6.283185307179586, 0.0, 1.0,
                     std::vector<double>(1024, 0.5)};
    residual.color_scale = Heatmap::ColorScale::Diverging;
    residual.min_color_limit = 4.0;
    Plot maps;
    maps.kind = Plot::Kind::Heatmaps;
    maps.heatmaps = {Heatmap{"observed", 32, 32, 0.0, 6.283185307179586, 0.0, 1.0, std::vector<double>(1024, 976.0)},
                     residual};
    r.plots = {maps};
    return r;
}

TEST(PlotMarks, UnbinnedRingsKuipersExcursionsAndTheLargestAndersonDarlingTerm) {
    const CheckResult r = marked(testing::sample_unbinned_pass(kLevel));
    const Plot& plot = r.plots[0];
    ASSERT_EQ(plot.highlights.size(), 3u);
    EXPECT_EQ(plot.highlights[0].label, "phi: D\u207a");
    EXPECT_DOUBLE_EQ(plot.highlights[0].x, 0.30);
    EXPECT_EQ(plot.highlights[1].label, "phi: D\u207b");
    EXPECT_DOUBLE_EQ(plot.highlights[1].x, 0.70);
    // The tail point, not the curve's highest: 0.4^2 / (0.02 * 0.98) > 0.9^2 / 0.25.
    EXPECT_EQ(plot.highlights[2].label, "cos theta: largest A\u00b2 term");
    EXPECT_DOUBLE_EQ(plot.highlights[2].x, 0.02);
    const std::string svg = render_svg(plot);
    EXPECT_THAT(svg, HasSubstr(">phi: D\u207a</text>"));
    EXPECT_EQ(count_of(svg, "<circle "), 3u);
    EXPECT_THAT(plot.note, HasSubstr("KS is not judged"));
}

TEST(PlotMarks, Chi2MapRingsTheLargestResidualAndMarksWhereOneCellAloneFails) {
    const CheckResult r = marked(chi2_row(0.887, 0.144));
    const Plot& plot = r.plots[0];
    ASSERT_EQ(plot.cells.size(), 1u);
    EXPECT_EQ(plot.cells[0].heatmap, 1u);
    EXPECT_EQ(plot.cells[0].row, 713 / 32);
    EXPECT_EQ(plot.cells[0].col, 713 % 32);
    ASSERT_EQ(plot.scale_marks.size(), 1u);
    // Two-sided normal tail at 1 - (1 - 0.2 level)^(1/1024) = 1.42e-08.
    EXPECT_NEAR(plot.scale_marks[0].value, 5.6707, 1e-3);
    const std::string svg = render_svg(plot);
    EXPECT_THAT(svg, HasSubstr("|r| = 5.7: one cell alone fails"));
    EXPECT_THAT(svg, HasSubstr(">largest |r|: -3.73</text>"));
    EXPECT_EQ(count_of(svg, "v16\" stroke=\"#c62828\""), 2u);  // at -5.67 and +5.67: the scale widened from the check's +-4
    EXPECT_THAT(plot.note, HasSubstr("Pearson's p < 0.8 \u00d7 level or the ringed largest residual's p < 0.2 \u00d7 "
                                     "level: one cell alone fails beyond |r| \u2248 5.7 (red marks)."));
    // bsdf_chi2 states its own shares, the landing test's among them.
    CheckResult bsdf = chi2_row(0.887, 0.144);
    bsdf.check_name = "bsdf_chi2";
    EXPECT_THAT(marked(bsdf).plots[0].note, HasSubstr("Pearson's p < 0.7 \u00d7 level, the ringed largest residual's p "
                                                      "< 0.2 \u00d7 level or the landing share's p < 0.1 \u00d7 level"));
}

// Once per-cell p-values underflow to 0, every cell at 0 ties and the check
// names the first of them (-43.35 here, where the table lists -109 first):
// the ring goes to the largest |residual| (the Judged line names the check's own cell).
TEST(PlotMarks, Chi2RingsTheTrulyLargestResidualWhenPValuesUnderflow) {
    CheckResult r = chi2_row(0.0, 0.0);
    for (Figure& f : r.figures) {
        if (f.name == "local_max_residual") f.value = -43.35;
        if (f.name == "local_cell") f.value = 5;
    }
    std::vector<double>& residuals = r.plots[0].heatmaps[1].values;
    residuals[5] = -43.35;
    residuals[700] = 60.0;
    residuals[713] = -109.0;
    residuals[800] = std::nan("");
    const CheckResult tied = marked(r);
    ASSERT_EQ(tied.plots[0].cells.size(), 1u);
    EXPECT_EQ(tied.plots[0].cells[0].row, 713 / 32);
    EXPECT_EQ(tied.plots[0].cells[0].col, 713 % 32);
    EXPECT_EQ(tied.plots[0].cells[0].label, "largest |r|: -109.00");
    // A p-value that did not underflow decides the cell itself: the check's stays.
    for (Figure& f : r.figures)
        if (f.name == "local_p_value") f.value = 1e-300;
    const CheckResult kept = marked(r);
    ASSERT_EQ(kept.plots[0].cells.size(), 1u);
    EXPECT_EQ(kept.plots[0].cells[0].col, 5);
    EXPECT_EQ(kept.plots[0].cells[0].label, "largest |r|: -43.35");
}

// Marks wait for the level: a row whose level is not settled (or an error
// row) gets no single-cell limit, and an error or n/a row no marks at all.
TEST(PlotMarks, NoLevelNoLimitAndAnErrorRowIsNotMarked) {
    CheckResult r = chi2_row(0.887, 0.144);
    r.level.reset();
    const CheckResult unlevelled = marked(r);
    EXPECT_THAT(unlevelled.plots[0].scale_marks, IsEmpty());
    EXPECT_EQ(unlevelled.plots[0].cells.size(), 1u);
    r.verdict = Verdict::Error;
    EXPECT_FALSE(marked(r).plots[0].marked());
}

TEST(PlotMarks, RoundTripHistogramShowsItsToleranceEvenBeyondEveryError) {
    CheckResult r = testing::sample_roundtrip_pass();  // errors 1e-12 .. 1e-7 by decade
    r.plots[0].log_x = false;
    r.plots[0].series[0].x = {-12, -11, -10, -9, -8, -7};
    r.figures = {{"tolerance", 1e-3}};
    r = marked(r);
    ASSERT_EQ(r.plots[0].limits.size(), 1u);
    EXPECT_NEAR(r.plots[0].limits[0].value, -3.5, 1e-12);  // log10(1e-3) - 1/2: in the slot of decade -3
    EXPECT_THAT(r.plots[0].note, HasSubstr("the dashed line stands at the tolerance's place in its decade"));
    const std::string svg = render_svg(r.plots[0]);
    EXPECT_THAT(svg, HasSubstr(">tolerance 0.001</text>"));
}

TEST(PlotMarks, ExhaustivePlotRingsTheMostBiasedFloatAndOutputsOutsideTheInterval) {
    CheckResult r = testing::sample_exhaustive_pass();
    r.figures = {{"most_biased_float", 0.99999994}, {"most_biased_count", 383}, {"most_biased_ideal", 256}};
    r.tables = {{"Outputs outside [a, b)", {"value", "inputs"}, {{"1 (0x1p+0)", "256"}}}};
    r = marked(r);
    const Plot& plot = r.plots[0];
    ASSERT_EQ(plot.highlights.size(), 2u);
    EXPECT_EQ(plot.highlights[0].x, -1.0);  // 0.99999994 is in [2^-1, 2^0)
    EXPECT_EQ(plot.highlights[0].y, 383.0);
    EXPECT_EQ(plot.highlights[1].x, 0.0);  // 1.0 is in [2^0, 2^1)
    EXPECT_EQ(plot.highlights[1].label, "outside [a, b): 1 \u00d7256");
    EXPECT_THAT(render_svg(plot), HasSubstr(">most biased: 0.99999994 \u00d7383 (ideal 256)</text>"));
}

}  // namespace
}  // namespace warpcheck
