// A check's judgement in its result (validate/checks/judged.h): each check's
// rules turn its figures into the lines a report draws — its p-value split
// into the tests it combines at their shares of the level, each limit with
// its state, counts reported beside the verdict, and the generic tolerance
// lines for a check that declares nothing. NaN is never within.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <limits>
#include <string>
#include <vector>

#include "validate/api/registry.h"
#include "validate/checks/bsdf/bsdf_checks.h"
#include "validate/checks/checks.h"
#include "validate/checks/judged.h"

namespace warpcheck {
namespace {

using ::testing::ElementsAre;
using State = JudgedQuantity::State;

constexpr double kLevel = 7.28e-05;

CheckResult row(std::string check, Verdict v, std::vector<Figure> figures) {
    CheckResult r;
    r.check_name = std::move(check);
    r.verdict = v;
    r.figures = std::move(figures);
    return r;
}

CheckResult p_row(std::string check, double p, std::vector<Figure> figures) {
    CheckResult r = row(std::move(check), Verdict::Pass, std::move(figures));
    r.p_value = p;
    r.level = kLevel;
    if (!(p >= kLevel)) r.verdict = Verdict::Fail;
    return r;
}

/// A chi-square row as the chi2 check writes it: Pearson's p and the largest
/// residual's, combined as min(P / 0.8, L / 0.2).
CheckResult chi2_row(double pearson, double local) {
    return p_row("chi2", std::min({1.0, pearson / 0.8, local / 0.2}),
                 {{"statistic", 968.5709}, {"dof", 1023}, {"p_value", pearson}, {"integral", 0.99999996},
                  {"integral_tolerance", 9.5e-07}, {"cells", 1024}, {"outside", 0}, {"local_max_residual", -3.73},
                  {"local_cell", 713}, {"local_p_value", local}});
}

std::vector<JudgedQuantity> lines_of(const CheckResult& r, const Check& check) {
    return judged_lines(r, check.judged_rules());
}

std::vector<std::string> quantities(const std::vector<JudgedQuantity>& lines) {
    std::vector<std::string> out;
    for (const auto& l : lines) out.push_back(l.quantity);
    return out;
}

const JudgedQuantity* line_starting(const std::vector<JudgedQuantity>& lines, std::string_view start) {
    for (const auto& l : lines)
        if (l.quantity.starts_with(start)) return &l;
    return nullptr;
}
// A pointer into a temporary vector would dangle.
const JudgedQuantity* line_starting(std::vector<JudgedQuantity>&& lines, std::string_view start) = delete;

TEST(Judged, Chi2SplitsItsPValueIntoPearsonAndTheLargestResidual) {
    const auto lines = lines_of(chi2_row(0.887, 0.144), *make_chi2_check());
    const auto* pearson = line_starting(lines, "Pearson X\u00b2 = 968.6 on 1023 dof");
    const auto* local = line_starting(lines, "largest cell residual -3.73 (cell 713)");
    const auto* combined = line_starting(lines, "p-value: min(Pearson / 0.8, residual / 0.2)");
    ASSERT_TRUE(pearson && local && combined);
    EXPECT_EQ(pearson->value, "0.887");
    EXPECT_EQ(pearson->limit, "\u2265 5.82e-05 (0.8 \u00d7 level)");
    EXPECT_EQ(local->limit, "\u2265 1.46e-05 (0.2 \u00d7 level)");
    EXPECT_EQ(combined->value, "0.72");
    EXPECT_EQ(combined->state, State::Within);
    const auto* integral = line_starting(lines, "integral of the density");
    ASSERT_TRUE(integral);
    EXPECT_EQ(integral->limit, "|x \u2212 1| \u2264 9.5e-07");
}

TEST(Judged, ALargeResidualFailsItsShareWhilePearsonPassesAndNaNIsNeverWithin) {
    const auto lines = lines_of(chi2_row(0.5, 1e-7), *make_chi2_check());
    EXPECT_EQ(line_starting(lines, "Pearson")->state, State::Within);
    EXPECT_EQ(line_starting(lines, "largest cell residual")->state, State::Beyond);
    EXPECT_EQ(line_starting(lines, "p-value: min")->state, State::Beyond);
    CheckResult r = chi2_row(0.887, 0.144);
    r.p_value = std::numeric_limits<double>::quiet_NaN();
    const auto nan = lines_of(r, *make_chi2_check());
    const auto* combined = line_starting(nan, "p-value: min");
    ASSERT_TRUE(combined);
    EXPECT_EQ(combined->value, "NaN");
    EXPECT_EQ(combined->state, State::Beyond);
}

TEST(Judged, UnbinnedJudgesEachMarginalAtItsSidakShareOfTheLevel) {
    CheckResult r = p_row("unbinned", -std::expm1(2.0 * std::log1p(-0.01)),
                          {{"tests", 2}, {"phi_kuiper_statistic", 0.0012}, {"phi_kuiper_p_value", 0.53},
                           {"phi_ad_statistic", 0.97}, {"phi_ad_p_value", 0.37}, {"cos_theta_ad_statistic", 6.65},
                           {"cos_theta_ad_p_value", 0.01}});
    r.tables = {{"Unbinned tests per marginal", {"marginal", "test", "judged", "statistic", "p-value"},
                 {{"phi", "kuiper", "yes", "0.0012", "0.53"}, {"phi", "ad", "no", "0.97", "0.37"},
                  {"cos theta", "ad", "yes", "6.65", "0.01"}}}};
    const auto lines = lines_of(r, *make_unbinned_check());
    EXPECT_THAT(quantities(lines), ElementsAre("phi: Kuiper V = 0.0012, p-value",
                                               "cos theta: Anderson\u2013Darling A\u00b2 = 6.65, p-value",
                                               "p-value: smallest judged p, \u0160id\u00e1k-corrected over the judged tests"));
    EXPECT_EQ(lines[0].limit, "\u2265 3.64e-05 (level, \u0160id\u00e1k over 2)");
    EXPECT_EQ(lines[1].value, "0.01");
}

TEST(Judged, ToleranceRulesCountsAndExcusesOfARoundTrip) {
    const CheckResult r = row("roundtrip", Verdict::Fail,
                              {{"max_error", 2e-5}, {"tolerance", 1e-5}, {"failures", 3.0}, {"resolution_limited", 7}});
    const auto lines = lines_of(r, *make_roundtrip_check());
    const auto* error = line_starting(lines, "largest |invert(sample(u)) \u2212 u|");
    ASSERT_TRUE(error);
    EXPECT_EQ(error->limit, "\u2264 1e-05");
    EXPECT_EQ(error->state, State::Beyond);
    EXPECT_EQ(line_starting(lines, "inputs beyond the tolerance")->state, State::Beyond);
    const auto* excused = line_starting(lines, "resolution-limited");
    ASSERT_TRUE(excused);
    EXPECT_EQ(excused->limit, "counted");
    EXPECT_EQ(excused->state, State::Reported);
}

// Each line with a numeric limit carries how near it is as a number, which
// the terminal and HTML margins read (reports/terminal_table.h, row_margin):
// a size over the limit it must stay under, a p-value over its limit; a count
// that must be 0, a reported count and an exact rule (tolerance 0) carry none.
TEST(Judged, EachLimitCarriesItsMarginAsANumber) {
    using Margin = JudgedQuantity::Margin;
    const auto chi2 = lines_of(chi2_row(0.887, 0.144), *make_chi2_check());
    const auto* integral = line_starting(chi2, "integral of the density");
    ASSERT_TRUE(integral);
    EXPECT_EQ(integral->margin_kind, Margin::OfLimit);
    EXPECT_NEAR(integral->margin, 4e-8 / 9.5e-7, 1e-6) << "an integral is held by its distance from 1";
    const auto* pearson = line_starting(chi2, "Pearson");
    ASSERT_TRUE(pearson);
    EXPECT_EQ(pearson->margin_kind, Margin::POverLimit);
    EXPECT_NEAR(pearson->margin, 0.887 / (0.8 * kLevel), 1e-6);

    const CheckResult trip = row("roundtrip", Verdict::Fail,
                                 {{"max_error", 2e-5}, {"tolerance", 1e-5}, {"failures", 3.0}, {"resolution_limited", 7}});
    const auto lines = lines_of(trip, *make_roundtrip_check());
    EXPECT_EQ(line_starting(lines, "largest |invert")->margin_kind, Margin::OfLimit);
    EXPECT_DOUBLE_EQ(line_starting(lines, "largest |invert")->margin, 2.0);
    EXPECT_EQ(line_starting(lines, "inputs beyond the tolerance")->margin_kind, Margin::None);
    EXPECT_EQ(line_starting(lines, "resolution-limited")->margin_kind, Margin::None);
    const CheckResult exact = row("roundtrip", Verdict::Pass, {{"max_error", 0}, {"tolerance", 0}, {"failures", 0}});
    for (const auto& l : lines_of(exact, *make_roundtrip_check())) EXPECT_EQ(l.margin_kind, Margin::None) << l.quantity;

    // A figure judged by name alone (no rule declared it): *_over_tolerance as it is.
    const CheckResult generic = row("a_check_of_its_own", Verdict::Pass, {{"pdf_error_over_tolerance", 0.37}});
    const auto g = judged_lines(generic, JudgedRules{});
    ASSERT_EQ(g.size(), 1u);
    EXPECT_EQ(g[0].margin_kind, Margin::OfLimit);
    EXPECT_DOUBLE_EQ(g[0].margin, 0.37);
    // A NaN size keeps a NaN margin beside a line that is beyond.
    const CheckResult nan = row("roundtrip", Verdict::Fail, {{"max_error", std::nan("")}, {"tolerance", 1e-5}});
    const auto nan_lines = lines_of(nan, *make_roundtrip_check());
    const auto* n = line_starting(nan_lines, "largest |invert");
    ASSERT_TRUE(n);
    EXPECT_EQ(n->state, State::Beyond);
    EXPECT_TRUE(std::isnan(n->margin));
}

TEST(Judged, ConsistencyBoundsTheZeroPdfsOfFloatRoundingByTheirPoissonBound) {
    CheckResult r = row("consistency", Verdict::Pass,
                        {{"zero_pdf", 0}, {"zero_pdf_rounded_random", 12}, {"zero_pdf_rounded_edge_inputs", 3},
                         {"zero_pdf_rounded_bound", 44}});
    const auto check = make_consistency_check();
    const auto lines = lines_of(r, *check);
    const auto* rounded = line_starting(lines, "random samples with pdf 0 beside a positive pdf");
    ASSERT_TRUE(rounded);
    EXPECT_EQ(rounded->limit, "\u2264 44");
    EXPECT_EQ(rounded->state, State::Within);
    r.figures[1].value = 45;  // one past the bound: the check fails, and so does the line
    const auto beyond = lines_of(r, *check);
    EXPECT_EQ(line_starting(beyond, "random samples with pdf 0")->state, State::Beyond);
    EXPECT_EQ(line_starting(beyond, "edge inputs with pdf 0")->state, State::Reported);
}

TEST(Judged, BinadeSharesTheLevelOverTheTestsItMade) {
    CheckResult r = p_row("binade", std::min(1.0, 3 * 1e-5),
                          {{"mass_p_value", 0.4}, {"parity_p_value", 0.2}, {"resolution_p_value", 1e-5}});
    const auto check = make_binade_check();
    auto lines = lines_of(r, *check);
    const auto* digits = line_starting(lines, "binary digits");
    ASSERT_TRUE(digits);
    EXPECT_EQ(digits->limit, "\u2265 2.43e-05 (level / 3)");
    EXPECT_EQ(digits->state, State::Beyond);
    r.figures[2].value = std::numeric_limits<double>::quiet_NaN();  // the digits not tested: two tests share the level
    r.p_value = 0.4;
    lines = lines_of(r, *check);
    EXPECT_EQ(line_starting(lines, "binary digits"), nullptr);
    EXPECT_EQ(line_starting(lines, "mass per binade")->limit, "\u2265 3.64e-05 (level / 2)");
}

TEST(Judged, BsdfChi2SplitsItsPValueIntoPearsonTheLargestResidualAndTheLandingShare) {
    CheckResult r = p_row("bsdf_chi2", std::min({1.0, 0.5 / 0.7, 0.3 / 0.2, 0.01 / 0.1}),
                          {{"statistic", 1000}, {"dof", 1023}, {"pearson_p_value", 0.5}, {"local_p_value", 0.3},
                           {"local_max_residual", 3.1}, {"landing_p_value", 0.01}, {"continuous_samples", 917000},
                           {"samples", 1000000}, {"delta_samples", 0}, {"pdf_integral", 0.917},
                           {"integral_tolerance", 1e-6}, {"delta_claimed", 0}});
    r.level = 1e-4;
    const auto check = bsdf::make_bsdf_chi2_check();
    const auto lines = lines_of(r, *check);
    ASSERT_GE(lines.size(), 5u);
    EXPECT_EQ(lines[0].limit, "\u2265 7.00e-05 (0.7 \u00d7 level)");
    EXPECT_THAT(lines[2].quantity, ::testing::HasSubstr("share of draws that landed (917\u202f000 of 1\u202f000\u202f000)"));
    EXPECT_EQ(lines[2].limit, "\u2265 1.00e-05 (0.1 \u00d7 level)");
    EXPECT_EQ(lines[3].quantity, "p-value: min(Pearson / 0.7, residual / 0.2, landing / 0.1), at most 1");
    EXPECT_EQ(lines[4].quantity, "pdf(wo, .) integrated over the sphere");
    EXPECT_EQ(lines[4].state, State::Within);
    for (Figure& f : r.figures)
        if (f.name == "pdf_integral") f.value = 1.01;
    EXPECT_EQ(lines_of(r, *check)[4].state, State::Beyond);
}

TEST(Judged, BsdfAlbedoHoldsTheEnergyAlbedoToOne) {
    CheckResult r = p_row("bsdf_albedo", 0.4, {{"energy_albedo", 0.8314}, {"energy_tolerance", 1e-6}, {"albedo_known", 1}});
    const auto check = bsdf::make_bsdf_albedo_check();
    const auto energy = [&] {
        for (const auto& l : lines_of(r, *check))
            if (l.quantity == "energy albedo") return l;
        return JudgedQuantity{};
    };
    EXPECT_EQ(energy().limit, "\u2264 1 + 1e-06");
    EXPECT_EQ(energy().state, State::Within);
    for (Figure& f : r.figures)
        if (f.name == "energy_albedo") f.value = std::nan("");
    EXPECT_EQ(energy().state, State::Beyond);  // NaN is never within
}

// Each check explains itself in the report (Check::legend, carried by the run):
// what it judges, and for a statistical check how its p-value is formed, so
// that reports/ renders the legend of any check without naming one.
TEST(Judged, EveryBuiltinCheckStatesItsLegendAndAStatisticalOneItsPValue) {
    Registry registry;
    register_builtin_checks(registry);
    ASSERT_GE(registry.checks().size(), 25u);
    std::vector<std::string> missing;
    for (const auto& check : registry.checks()) {
        const CheckLegend legend = check->legend();
        EXPECT_EQ(legend.check, check->name());
        if (legend.judged.empty() || legend.judged == check->description()) missing.push_back(check->name() + ": judged");
        if (check->statistical() && legend.p_value.empty()) missing.push_back(check->name() + ": p-value");
    }
    EXPECT_THAT(missing, ::testing::IsEmpty());
}

/// The code of a source file without its // comments (a "//" inside a string literal kept).
std::string code_without_comments(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::string out, line;
    while (std::getline(in, line)) {
        bool in_string = false;
        for (std::size_t i = 0; i < line.size(); ++i) {
            if (in_string && line[i] == '\\') {
                out += line[i++];
            } else if (line[i] == '"') {
                in_string = !in_string;
            } else if (!in_string && line.compare(i, 2, "//") == 0) {
                break;
            }
            if (i < line.size()) out += line[i];
        }
        out += '\n';
    }
    return out;
}

// A check's rule lives with the check (issue 35): reports/ renders any check
// from what its rows and its run carry (the judged lines, the legends, the
// plots' marks and notes), and names none: a check-name literal in the code of
// any file of reports/ fails.
TEST(Judged, ReportsNameNoCheck) {
    Registry registry;
    register_builtin_checks(registry);
    std::map<std::string, int> named;  // file -> check-name literals in its code
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(WARPCHECK_SOURCE_DIR) / "reports")) {
        const auto ext = entry.path().extension();
        if (ext != ".cpp" && ext != ".h") continue;
        const std::string code = code_without_comments(entry.path());
        for (const auto& check : registry.checks())
            for (std::size_t at = code.find('"' + check->name() + '"'); at != std::string::npos;
                 at = code.find('"' + check->name() + '"', at + 1))
                ++named[entry.path().filename().string()];
    }
    EXPECT_THAT(named, ::testing::IsEmpty()) << "check names in reports/";
}

TEST(Judged, ACheckThatDeclaresNothingGetsTheGenericToleranceRules) {
    CheckResult r = row("someday", Verdict::Pass,
                        {{"max_x_error_over_tolerance", 1.2}, {"integral", 1.01}, {"integral_tolerance", 0.001},
                         {"other", 5}});
    const auto lines = judged_lines(r, {});
    EXPECT_THAT(quantities(lines), ElementsAre("max_x_error_over_tolerance", "integral"));
    EXPECT_EQ(lines[0].state, State::Beyond);
    EXPECT_EQ(lines[1].state, State::Beyond);  // |1.01 - 1| > 0.001
    // Errors and n/a rows judged nothing.
    r.verdict = Verdict::Error;
    record_judgement(r, {});
    EXPECT_TRUE(r.judged.empty());
}

}  // namespace
}  // namespace warpcheck
