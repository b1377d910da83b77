// The terminal table: fits its width, says how far each key figure is from its
// limit, summarises by family, lists the weakest passes, and says so when
// --failures-only has nothing to show.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "reports/terminal_table.h"
#include "reports/text.h"

namespace warpcheck {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

/// A judged line held under `limit`, with its margin, as a check writes it
/// (validate/checks/judged.h: with_margin): the margins are read from these.
JudgedQuantity held(std::string quantity, double size, double limit) {
    JudgedQuantity j{std::move(quantity), std::to_string(size), "\u2264 " + std::to_string(limit),
                     size <= limit ? JudgedQuantity::State::Within : JudgedQuantity::State::Beyond};
    j.margin_kind = JudgedQuantity::Margin::OfLimit;
    j.margin = size / limit;
    return j;
}

/// An exact rule's line (a count that must be 0): no margin.
JudgedQuantity exact(std::string quantity, double count) {
    return {std::move(quantity), std::to_string(count), "= 0",
            count == 0.0 ? JudgedQuantity::State::Within : JudgedQuantity::State::Beyond};
}

CheckResult result(std::string case_name, std::string check, Verdict verdict, std::string summary,
                   std::vector<Figure> figures = {}, std::vector<JudgedQuantity> judged = {}) {
    CheckResult r;
    r.case_name = std::move(case_name);
    r.check_name = std::move(check);
    r.verdict = verdict;
    r.summary = std::move(summary);
    r.figures = std::move(figures);
    r.judged = std::move(judged);
    r.rerun_command = "validate --filter '" + r.case_name + "' --check " + r.check_name;
    return r;
}

CheckResult statistical(std::string case_name, double p, double level) {
    CheckResult r = result(std::move(case_name), "chi2", Verdict::Pass, "chi2 1000.0 dof 1000 p " + std::to_string(p));
    r.p_value = p;
    r.level = level;
    if (!(p >= level)) r.verdict = Verdict::Fail;
    return r;
}

/// Rows as the built-in checks write them: long names and long key figures.
RunResult long_run() {
    RunResult run;
    const std::string tr = "trowbridge_reitz_visible[ax=0.3,ay=0.05,theta_o=60]";
    run.results = {
        result("cosine_power_hemisphere[exponent=50]", "tabulated", Verdict::Pass,
               "cos theta: max |dx| 1.30e-01 (0.17 of tol), pdf 1.00e+00 (0.37 of tol); phi: max |dx| 5.45e-07 (0.05 "
               "of tol), pdf 0.00e+00 (0.00 of tol)",
               {{"cos_theta_max_x_error_over_tolerance", 0.17}, {"cos_theta_max_pdf_error_over_tolerance", 0.37},
                {"phi_max_x_error_over_tolerance", 0.05}},
               {held("cos_theta_max_x_error_over_tolerance", 0.17, 1.0),
                held("cos_theta_max_pdf_error_over_tolerance", 0.37, 1.0),
                held("phi_max_x_error_over_tolerance", 0.05, 1.0)}),
        result(tr, "roundtrip", Verdict::Pass, "max |du| 3.87e-07",
               {{"max_error", 3.87e-07}, {"tolerance", 1.52587890625e-05}},
               {held("max_error", 3.87e-07, 1.52587890625e-05), exact("failures", 0)}),
        statistical(tr, 0.43, 7.28e-05),
        statistical("trowbridge_reitz_normals[ax=0.3,ay=0.05]", 0.0029, 7.28e-05),
        result("uniform_float_interval[a=0,b=1]", "roundtrip", Verdict::Pass, "exact inverse",
               {{"max_error", 0}, {"tolerance", 0}}, {exact("failures", 0)}),
    };
    return run;
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

TEST(TerminalTable, DefaultFitsOneHundredTwentyColumns) {
    std::ostringstream out;
    print_table(long_run(), out);
    std::size_t rows = 0;
    for (const std::string& line : lines(out.str())) {
        EXPECT_LE(display_width(line), 120u) << line;
        rows += line.starts_with("pass ");
    }
    EXPECT_EQ(rows, 5u);
    // The parameters stay whole; the family gives way in its middle.
    EXPECT_THAT(out.str(), HasSubstr("trowb…sible[ax=0.3,ay=0.05,theta_o=60]"));
    EXPECT_THAT(out.str(), HasSubstr("cos theta: max |dx| 1.30e-01"));
    EXPECT_THAT(out.str(), Not(HasSubstr("pdf 0.00e+00 (0.00 of tol)"))) << "the long key figure is cut";
}

TEST(TerminalTable, WideKeepsEverything) {
    std::ostringstream out;
    TableStyle wide;
    wide.width = 0;
    print_table(long_run(), out, wide);
    EXPECT_THAT(out.str(), HasSubstr("trowbridge_reitz_visible[ax=0.3,ay=0.05,theta_o=60]"));
    EXPECT_THAT(out.str(), HasSubstr("phi: max |dx| 5.45e-07 (0.05 of tol), pdf 0.00e+00 (0.00 of tol)"));
}

// The margin says what a key figure is against its limit: an alarming-looking
// "max |dx| 1.30e-01" is 0.37 of its tolerance at most. It is read from the
// judged lines the check wrote, never from figure names.
TEST(TerminalTable, MarginOfEachKindOfLimit) {
    const RunResult run = long_run();
    const RowMargin tabulated = row_margin(run.results[0]);
    ASSERT_TRUE(tabulated.of_tolerance);
    EXPECT_DOUBLE_EQ(*tabulated.of_tolerance, 0.37);
    EXPECT_EQ(tabulated.tolerance_figure, "cos_theta_max_pdf_error_over_tolerance");
    EXPECT_EQ(margin_text(tabulated), "0.37 of tol");
    EXPECT_NEAR(*row_margin(run.results[1]).of_tolerance, 3.87e-07 / 1.52587890625e-05, 1e-12);
    EXPECT_EQ(margin_text(row_margin(run.results[1])), "0.025 of tol");
    EXPECT_EQ(margin_text(row_margin(run.results[2])), ">1000x level");
    EXPECT_EQ(margin_text(row_margin(run.results[3])), "40x level");
    EXPECT_FALSE(row_margin(run.results[4]).of_tolerance) << "a tolerance of 0 is an exact rule, not a fraction";
    CheckResult unjudged = result("c", "chi2", Verdict::Pass, "", {{"integral", 1.000002}, {"integral_tolerance", 4e-6},
                                                                   {"error_over_tolerance", 0.5}});
    EXPECT_FALSE(row_margin(unjudged).of_tolerance) << "figure names are not read: no judged line, no margin";
    CheckResult nan = result("d", "pmf", Verdict::Fail, "", {},
                             {held("sum", 0.25, 1.0), held("mass", std::nan(""), 1.0)});
    EXPECT_NEAR(*row_margin(nan).of_tolerance, 0.25, 1e-12) << "a NaN margin is no number to show";
    CheckResult failing = statistical("f", 1e-9, 7.28e-05);
    EXPECT_EQ(margin_text(row_margin(failing)), "1.4e-5x level");
    CheckResult nan_p = statistical("n", std::nan(""), 7.28e-05);
    EXPECT_EQ(margin_text(row_margin(nan_p)), "NaNx level");
}

// A row that failed for another reason than its margin shows none: "0.25 of
// tol" beside a FAIL would read as if the error were the cause.
TEST(TerminalTable, FailedRowShowsOnlyAMarginPastItsLimit) {
    RunResult run;
    run.results = {result("lerp[a=1]", "roundtrip", Verdict::Fail, "max |du| 5.96e-08",
                          {{"max_error", 5.96e-08}, {"tolerance", 1.52587890625e-05}},
                          {held("max_error", 5.96e-08, 1.52587890625e-05), exact("outside_input_domain", 2)}),
                   result("lerp[a=2]", "roundtrip", Verdict::Fail, "max |du| 0.5",
                          {{"max_error", 0.5}, {"tolerance", 1.52587890625e-05}},
                          {held("max_error", 0.5, 1.52587890625e-05)}),
                   statistical("power_wrong[n=2]", 1e-30, 7.28e-05)};
    std::ostringstream out;
    print_table(run, out);
    EXPECT_THAT(out.str(), Not(HasSubstr("of tol  max |du| 5.96e-08")));
    EXPECT_THAT(out.str(), HasSubstr("3.3e4 of tol    max |du| 0.5"));
    EXPECT_THAT(out.str(), HasSubstr("1.4e-26x level  chi2"));
}

TEST(TerminalTable, WeakestPassesAreListed) {
    std::ostringstream out;
    print_table(long_run(), out);
    const std::string text = out.str();
    const std::size_t at = text.find("Closest to their limits");
    ASSERT_NE(at, std::string::npos) << text;
    const std::string list = text.substr(at);
    EXPECT_THAT(list, HasSubstr("40x level     chi2       trowbridge_reitz_normals[ax=0.3,ay=0.05]  (p-value)"));
    EXPECT_THAT(list, HasSubstr("0.37 of tol   tabulated  cosine_power_hemisphere[exponent=50]  "
                                "(cos_theta_max_pdf_error_over_tolerance)"));
    // Smallest p against the level first, then the largest fractions of a tolerance.
    EXPECT_LT(list.find("40x level"), list.find("5907x level"));
    EXPECT_LT(list.find("5907x level"), list.find("0.37 of tol"));
    EXPECT_LT(list.find("0.37 of tol"), list.find("0.025 of tol"));
    EXPECT_THAT(list, Not(HasSubstr("uniform_float_interval"))) << "an exact rule has no fraction to list";
}

// bsdf_reciprocity judges its largest relative error against its tolerance:
// a rough dielectric at 0.996 of it is among the closest to their limits.
TEST(TerminalTable, ReciprocityRowsHaveAMargin) {
    RunResult run = long_run();
    run.results.push_back(result("rough_dielectric[alpha=0.3,eta=1.5,theta_o=85]", "bsdf_reciprocity", Verdict::Pass,
                                 "max rel. error 0.000243 over 67990 pairs, 35 at float resolution",
                                 {{"max_relative_error", 0.996 * 0x1p-12}, {"tolerance", 0x1p-12}},
                                 {held("max_relative_error", 0.996 * 0x1p-12, 0x1p-12)}));
    const RowMargin m = row_margin(run.results.back());
    ASSERT_TRUE(m.of_tolerance);
    EXPECT_NEAR(*m.of_tolerance, 0.996, 1e-12);
    EXPECT_EQ(m.tolerance_figure, "max_relative_error");
    std::ostringstream out;
    print_table(run, out);
    const std::string text = out.str();
    const std::size_t at = text.find("Closest to their limits");
    ASSERT_NE(at, std::string::npos) << text;
    const std::vector<std::string> listed = lines(text.substr(at));
    const auto row = std::find_if(listed.begin(), listed.end(),
                                  [](const std::string& l) { return l.find("bsdf_reciprocity") != std::string::npos; });
    ASSERT_NE(row, listed.end()) << text;
    EXPECT_TRUE(row->starts_with("  1 of tol ")) << *row;
    EXPECT_THAT(*row, HasSubstr("(max_relative_error)"));
}

TEST(TerminalTable, FamilySummaryCountsVerdicts) {
    RunResult run = long_run();
    run.results.push_back(statistical("trowbridge_reitz_visible[ax=1,ay=1,theta_o=0]", 1e-9, 7.28e-05));
    CheckResult na = result("trowbridge_reitz_visible[ax=1,ay=1,theta_o=0]", "tabulated", Verdict::NotApplicable,
                            "not applicable: no view");
    run.results.push_back(na);
    std::ostringstream out;
    print_family_summary(run, out);
    EXPECT_THAT(out.str(), HasSubstr("  trowbridge_reitz_visible      2      2      1      -      1\n"));
    EXPECT_THAT(out.str(), HasSubstr("  uniform_float_interval        1      1      -      -      -\n"));
    std::ostringstream failures;
    print_family_summary(run, failures, true);
    EXPECT_THAT(failures.str(), HasSubstr("trowbridge_reitz_visible"));
    EXPECT_THAT(failures.str(), Not(HasSubstr("uniform_float_interval")));
}

TEST(TerminalTable, NoFamilySummaryForOneFamily) {
    RunResult run;
    run.results = {statistical("power[n=2]", 0.5, 1e-3), statistical("power[n=3]", 0.5, 1e-3)};
    std::ostringstream out;
    print_table(run, out);
    EXPECT_THAT(out.str(), Not(HasSubstr("By family")));
    run.results.push_back(statistical("cone[a=1]", 0.5, 1e-3));
    std::ostringstream two;
    print_table(run, two);
    EXPECT_THAT(two.str(), HasSubstr("By family"));
}

TEST(TerminalTable, FailuresOnlyOnAnAllPassRunSaysSo) {
    std::ostringstream out;
    TableStyle style;
    style.failures_only = true;
    print_table(long_run(), out, style);
    EXPECT_THAT(out.str(), HasSubstr("No failures: all 5 checks that ran passed.\n"));
    EXPECT_THAT(out.str(), Not(HasSubstr("key figure"))) << "no empty header";
    EXPECT_THAT(out.str(), Not(HasSubstr("By family")));
}

TEST(TerminalTable, FailuresOnlyShowsTheFailures) {
    RunResult run = long_run();
    run.results.push_back(statistical("power_wrong[n=2]", 1e-30, 7.28e-05));
    std::ostringstream out;
    TableStyle style;
    style.failures_only = true;
    print_table(run, out, style);
    EXPECT_THAT(out.str(), HasSubstr("FAIL   chi2   power_wrong[n=2]"));
    EXPECT_THAT(out.str(), Not(HasSubstr("\npass ")));
    EXPECT_THAT(out.str(), HasSubstr("What failed, and how to rerun it:\n  FAIL chi2 power_wrong[n=2]: "));
}

TEST(TerminalTable, ControlCharactersNeverReachTheTerminal) {
    RunResult run;
    run.results = {result("evil\x1b[2J[x=1]", "chi2", Verdict::Fail, "bad\rworse")};
    std::ostringstream out;
    print_table(run, out);
    EXPECT_THAT(out.str(), Not(HasSubstr("\x1b")));
    EXPECT_THAT(out.str(), Not(HasSubstr("\r")));
    EXPECT_THAT(out.str(), HasSubstr("evil\\x1b[2J[x=1]"));
}

TEST(TerminalTable, CaseNamesAreCutSensibly) {
    EXPECT_EQ(fit_case_name("short[a=1]", 20), "short[a=1]");
    EXPECT_EQ(fit_case_name("trowbridge_reitz_visible[ax=0.3,ay=0.05,theta_o=60]", 40),
              "trowbr…isible[ax=0.3,ay=0.05,theta_o=60]");
    EXPECT_EQ(display_width(fit_case_name("trowbridge_reitz_visible[ax=0.3,ay=0.05,theta_o=60]", 40)), 40u);
    // The family gives way to a lone "…" before a parameter is cut.
    EXPECT_EQ(fit_case_name("rough_conductor[alpha=0.05,theta_o=85]", 24), "…[alpha=0.05,theta_o=85]");
    EXPECT_EQ(fit_case_name("rough_conductor[alpha=0.05,theta_o=85]", 25), "r…[alpha=0.05,theta_o=85]");
    EXPECT_EQ(fit_case_name("rough_conductor[alpha=0.05,theta_o=85]", 26), "r…r[alpha=0.05,theta_o=85]");
    // Parameters too long to keep whole even so: the end gives way.
    EXPECT_EQ(fit_case_name("f[a_very_long_parameter_list=1]", 12), "f[a_very_lo…");
    EXPECT_EQ(fit_case_name("no_parameters_at_all", 8), "no_para…");
}

/// Rows of the widest built-in names, checks and margins: the longest
/// parameters (plastic's), five rough_conductor cases told apart only by
/// theirs, exhaustive_roundtrip, a hostile name and an n/a row.
RunResult widest_run() {
    RunResult run;
    const std::string key = "max rel. weight diff 6.88e-07, max ||wi| - 1| 5.96e-08 over 1000000 samples, 0 excused";
    for (const char* name :
         {"plastic[kd=0.8,eta=1.5,alpha=0.2,theta_o=60]", "rough_conductor[alpha=0.05,theta_o=0]",
          "rough_conductor[alpha=0.05,theta_o=30]", "rough_conductor[alpha=0.05,theta_o=60]",
          "rough_conductor[alpha=0.05,theta_o=85]", "rough_conductor[alpha=0.3,theta_o=85]",
          "rough_conductor_aniso[ax=0.3,ay=0.05,theta_o=60,phi_o=45]"})
        run.results.push_back(result(name, "bsdf_weight", Verdict::Pass, key,
                                     {{"max_relative_difference", 1e-9}, {"tolerance", 1.0}},
                                     {held("max_relative_difference", 1e-9, 1.0)}));
    run.results.push_back(statistical("uniform_float_interval[a=0.999,b=1.001]", 0.3, 7.28e-05));
    run.results.push_back(result("unit_float_mul32[a=1]", "exhaustive_roundtrip", Verdict::Pass, key,
                                 {{"max_error", 0.0078}, {"tolerance", 1.0}}, {held("max_error", 0.0078, 1.0)}));
    run.results.push_back(result("hostile_name\x1b[2J\x1b]0;owned\x07\r\n", "roundtrip", Verdict::Fail, key));
    run.results.push_back(result("smooth_dielectric[eta=1.5,theta_o=60]", "bsdf_reciprocity",
                                 Verdict::NotApplicable, "not applicable: only delta lobes: f is 0 everywhere"));
    return run;
}

// In a pipe (120 columns) and on a terminal of 100, every row fits and keeps
// its case's parameters whole: the five rough_conductor rows read apart.
TEST(TerminalTable, ParametersStayWholeInAPipeAndAtOneHundredColumns) {
    const RunResult run = widest_run();
    for (const std::size_t width : {std::size_t{120}, std::size_t{100}}) {
        TableStyle style;
        style.width = width;
        std::ostringstream out;
        print_table(run, out, style);
        const std::vector<std::string> all = lines(out.str());
        for (const CheckResult& r : run.results) {
            const std::string name = printable(r.case_name);
            const std::string params = name.substr(std::min(name.find('['), name.size()));
            const auto row = std::find_if(all.begin(), all.end(), [&](const std::string& line) {
                return line.find("  " + r.check_name + "  ") != std::string::npos &&
                       line.find(params + " ") != std::string::npos;
            });
            EXPECT_NE(row, all.end()) << width << " columns: no row of " << name << " with " << params << "\n"
                                      << out.str();
        }
        // Every line but the failures' messages and rerun commands, which are printed whole.
        bool failures = false;
        for (const std::string& line : all) {
            failures = failures || line.starts_with("What failed");
            if (failures && (line.starts_with("  ") || line.starts_with("What failed"))) continue;
            failures = false;
            EXPECT_LE(display_width(line), width) << line;
        }
    }
}

TEST(Text, ColumnsAndClock) {
    EXPECT_EQ(display_width("π≈3"), 3u);
    EXPECT_EQ(fit_columns("abcdef", 4), "abc…");
    EXPECT_EQ(fit_columns("abc", 4), "abc");
    EXPECT_EQ(fit_columns("ππππ", 3), "ππ…");
    EXPECT_EQ(format_clock(7.9), "0:07");
    EXPECT_EQ(format_clock(185), "3:05");
    EXPECT_EQ(format_clock(3723), "1:02:03");
    EXPECT_EQ(format_clock(std::nan("")), "--:--");
    EXPECT_EQ(printable("a\tb\x7f"), "a\\x09b\\x7f");
}

}  // namespace
}  // namespace warpcheck
