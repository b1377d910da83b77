// The result model's one description (reports/result.h): it names every member
// of every type, and the JSON report read back is the run written, member for
// member, whatever the verdicts, enumerators, optional numbers and doubles.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "reports/json_input.h"
#include "reports/render.h"
#include "support/model_visitors.h"

namespace warpcheck {
namespace {

using testing::aggregate_members;
using testing::described_members;

template <class T>
void expect_every_member_described(const char* name) {
    EXPECT_EQ(described_members<T>(), aggregate_members<T>())
        << name << ": a member is missing from its description `fields` in reports/result.h";
}

TEST(ResultModel, DescriptionsCoverEveryMember) {
    expect_every_member_described<Figure>("Figure");
    expect_every_member_described<Series>("Series");
    expect_every_member_described<Heatmap>("Heatmap");
    expect_every_member_described<LimitLine>("LimitLine");
    expect_every_member_described<Highlight>("Highlight");
    expect_every_member_described<CellHighlight>("CellHighlight");
    expect_every_member_described<ScaleMark>("ScaleMark");
    expect_every_member_described<Plot>("Plot");
    expect_every_member_described<Table>("Table");
    expect_every_member_described<FamilyValue>("FamilyValue");
    expect_every_member_described<FamilyPoint>("FamilyPoint");
    expect_every_member_described<PhaseTime>("PhaseTime");
    expect_every_member_described<CheckResult>("CheckResult");
    expect_every_member_described<RunInfo>("RunInfo");
    expect_every_member_described<CheckLegend>("CheckLegend");
    expect_every_member_described<Totals>("Totals");
}

// The guard itself: a type whose description leaves a member out is caught.
struct TwoMembers {
    int described = 0;
    bool forgotten = false;
};
template <class V, Model<TwoMembers> T>
void fields(V& v, T& t) {
    v("described", t.described);
}

TEST(ResultModel, TheGuardCatchesAForgottenMember) {
    EXPECT_EQ(aggregate_members<TwoMembers>(), 2);
    EXPECT_EQ(described_members<TwoMembers>(), 1);
}

/// Doubles JSON text must carry: the non-finite ones, -0, the smallest
/// subnormal, the largest double, and decimals that need all 17 digits.
std::vector<double> hard_doubles() {
    const double inf = std::numeric_limits<double>::infinity();
    return {std::numeric_limits<double>::quiet_NaN(), inf, -inf, -0.0, 4.9406564584124654e-324,
            std::numeric_limits<double>::max(), 0.1, 1.0 / 3.0, -2.5e-310, 7.28258687452138e-05};
}

/// Text JSON must escape; valid UTF-8 (the report replaces invalid bytes).
std::vector<std::string> hard_texts() {
    return {"plain", "quote\" back\\slash", "new\nline\ttab\x01", "unicode \xc3\xa9\xe2\x88\x9e", ""};
}

/// A run with every member of every type set, four rows (one per verdict,
/// n/a included), each with figures, phases, plots, heatmaps and tables.
RunResult every_member_run(int variant) {
    testing::FillVisitor fill(variant, hard_doubles(), hard_texts());
    RunResult run;
    fill.fill(run.info);
    run.results.resize(EnumNames<Verdict>::names.size());
    for (std::size_t i = 0; i < run.results.size(); ++i) {
        fill.fill(run.results[i]);
        run.results[i].verdict = static_cast<Verdict>(i);
    }
    return run;
}

TEST(ResultModel, JsonReadBackIsTheRunWrittenMemberForMember) {
    for (int variant = 0; variant < 4; ++variant) {
        const RunResult run = every_member_run(variant);
        ASSERT_GT(run.info.shard_count, 0u);  // so the optional "shard" group is written
        const std::string text = render_json(run);
        const JsonResults back = read_json_results(text);
        const auto written = testing::flatten(run.info, true), read = testing::flatten(back.run.info, true);
        EXPECT_EQ(read, written);
        ASSERT_EQ(back.run.results.size(), run.results.size());
        for (std::size_t i = 0; i < run.results.size(); ++i)
            EXPECT_EQ(testing::flatten(back.run.results[i], true), testing::flatten(run.results[i], true))
                << "row " << i;
        EXPECT_EQ(back.totals, run.totals());
        EXPECT_EQ(render_json(back.run), text);
        EXPECT_GT(written.size(), 15u);
    }
}

TEST(ResultModel, EveryVerdictAndPhasesSurviveTheJson) {
    const RunResult back = parse_json_results(render_json(every_member_run(0)));
    ASSERT_EQ(back.results.size(), 4u);
    EXPECT_EQ(back.results[3].verdict, Verdict::NotApplicable);
    EXPECT_EQ(back.results[0].verdict, Verdict::Pass);
    EXPECT_EQ(back.results[2].phases.size(), 3u);
    EXPECT_EQ(back.totals(), (Totals{4, 1, 1, 1, 1}));
}

// A judged line's margin is optional: a file written before it was added
// (or a line whose rule has none) reads as no margin, and one written with
// it comes back as it was.
TEST(ResultModel, AJudgedLineWithoutAMarginReadsAsNone) {
    RunResult run = every_member_run(1);
    ASSERT_FALSE(run.results.empty());
    JudgedQuantity with{"largest error", "0.5", "\u2264 1", JudgedQuantity::State::Within,
                        JudgedQuantity::Margin::OfLimit, 0.5};
    JudgedQuantity without{"failures", "0", "= 0", JudgedQuantity::State::Within};
    run.results[0].judged = {with, without};
    const RunResult back = parse_json_results(render_json(run));
    ASSERT_EQ(back.results[0].judged.size(), 2u);
    EXPECT_EQ(back.results[0].judged[0].margin_kind, JudgedQuantity::Margin::OfLimit);
    EXPECT_DOUBLE_EQ(back.results[0].judged[0].margin, 0.5);
    EXPECT_EQ(back.results[0].judged[1].margin_kind, JudgedQuantity::Margin::None);
    const std::string text = render_json(run);
    const std::size_t line = text.find("\"quantity\":\"failures\"");
    ASSERT_NE(line, std::string::npos);
    EXPECT_EQ(text.substr(line, text.find('}', line) - line).find("\"margin\""), std::string::npos)
        << "none is not written";
}

TEST(ResultModel, AReadErrorNamesThePlace) {
    RunResult run = every_member_run(1);
    std::string text = render_json(run);
    const std::string kind = "\"kind\":\"";
    text.insert(text.find(kind, text.find("\"plots\":")) + kind.size(), "pie");
    try {
        read_json_results(text);
        FAIL() << "a plot kind 'pie...' was read";
    } catch (const JsonInputError& e) {
        EXPECT_THAT(e.what(), ::testing::HasSubstr("results[0].plots[0].kind: 'pie"));
        EXPECT_THAT(e.what(), ::testing::HasSubstr("is not a plot kind"));
    }
}

}  // namespace
}  // namespace warpcheck
