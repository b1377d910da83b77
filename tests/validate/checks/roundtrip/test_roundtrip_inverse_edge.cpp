// Round trips across an edge of the inverse (issue 22): an environment map
// (an 8 x 8 piecewise-constant table, pbrt-v4's PiecewiseConstant2D with its
// inverse) samples y in row 5 and rounds it up onto 0.75, the edge of row 6,
// where the inverse (correctly) reads row 6, whose conditional CDF differs:
// u.x comes back 0.5 away. On today's main before the rule, seeds 9 and 16 of
// the hard catalogue's `environment_zero_rows` failed that way (1 input of
// 1,003,600). The correct map passes on 20 seeds and counts what it excused;
// an inverse that reads the wrong row within 1e-4 of an edge still fails, and
// one wrong on every other float (which each float neighbour would excuse)
// fails by the per-chunk bound.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "sampling/float_bits.h"
#include "hard/environment_map.h"
#include "hard/piecewise.h"
#include "support/check_harness.h"
#include "validate/api/warp_case.h"
#include "validate/checks/checks.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

enum class Inverse { Correct, WrongRowNearEdges, WrongOnOddFloats };

struct EnvironmentMap : hard::EnvironmentMap {
    Inverse inverse = Inverse::Correct;

    Point2f invert(Point2f p) const {
        const Point2f u = hard::EnvironmentMap::invert(p);
        // Wrong twins: within 1e-4 below a row edge, u.x from the next row's
        // conditional (a band of positive measure); or u.x off by 0.25 wherever
        // x.x's last significand bit is 1 (right at each float neighbour of those).
        if (inverse == Inverse::WrongRowNearEdges && std::ceil(p.y * 8.0f) - p.y * 8.0f < 8e-4f)
            return {map.invert({p.x, std::min(7.0f, std::ceil(p.y * 8.0f)) / 8.0f}).x, u.y};
        if (inverse == Inverse::WrongOnOddFloats && (float_to_bits(p.x) & 1u) != 0)
            return {std::fmod(u.x + 0.25f, 1.0f), u.y};
        return u;
    }
};

std::unique_ptr<WarpCase> environment(const std::string& name, Inverse inverse) {
    return make_warp_case({.family = name, .domain = chi2::Domain::unit_square()},
                          EnvironmentMap{{hard::PiecewiseConstant2D(hard::environment_image(), 8)}, inverse});
}

CheckResult roundtrip(const WarpCase& warp, uint64_t seed) {
    RunOptions options;
    options.samples = 1'000'000;
    options.threads = 2;
    options.seed = seed;
    options.check_time_budget = testing::kTestTimeBudget;
    const auto check = make_roundtrip_check();
    return run_jobs({Job{&warp, check.get()}}, options).results.at(0);
}

double figure(const CheckResult& r, const std::string& name) {
    const auto f = r.figure(name);
    EXPECT_TRUE(f.has_value()) << name;
    return f.value_or(std::nan(""));
}

TEST(RoundtripInverseEdge, AnEnvironmentMapRoundedOntoARowEdgePassesOnTwentySeeds) {
    // The catalogue's name, so the inputs are the catalogue's (the stream
    // depends on the case's name and the seed).
    const auto map = environment("environment_zero_rows", Inverse::Correct);
    double excused = 0.0;
    for (uint64_t seed = 1; seed <= 20; ++seed) {
        const CheckResult r = roundtrip(*map, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << "seed " << seed << ": " << r.message;
        EXPECT_LE(figure(r, "inverse_edge_most_in_a_chunk"), figure(r, "inverse_edge_chunk_bound")) << seed;
        excused += figure(r, "inverse_edge_random_inputs");
        if (seed == 9 || seed == 16) {  // the catalogue's two false failures
            EXPECT_EQ(figure(r, "inverse_edge_random_inputs"), 1.0) << "seed " << seed;
            EXPECT_NE(r.summary.find("1 across an inverse edge"), std::string::npos) << r.summary;
            bool listed = false;
            for (const Table& t : r.tables)
                for (const auto& row : t.rows) listed = listed || row.at(0) == "across an inverse edge";
            EXPECT_TRUE(listed) << "the excused input is listed";
        }
    }
    EXPECT_GE(excused, 2.0);
    EXPECT_LE(excused, 20.0) << "about 1 in 10 runs of 10^6 inputs round onto a row edge";
}

TEST(RoundtripInverseEdge, AnInverseThatReadsTheWrongRowNearItsEdgesFails) {
    const auto twin = environment("environment_wrong_row_near_edges", Inverse::WrongRowNearEdges);
    for (uint64_t seed = 1; seed <= 5; ++seed) {
        const CheckResult r = roundtrip(*twin, seed);
        EXPECT_EQ(r.verdict, Verdict::Fail) << "seed " << seed;
        // The band holds ~8e-4 / 8 of y per edge, rows 2..6 sampled: hundreds of inputs.
        EXPECT_GT(figure(r, "failures"), 100.0) << "seed " << seed;
        // Their float neighbours read the wrong row too: at most the few within 2
        // floats of the band's far side can be excused.
        EXPECT_LT(figure(r, "inverse_edge_random_inputs"), figure(r, "failures") / 100.0) << "seed " << seed;
    }
}

TEST(RoundtripInverseEdge, AnInverseWrongOnEveryOtherFloatFailsByTheBound) {
    const auto twin = environment("environment_wrong_on_odd_floats", Inverse::WrongOnOddFloats);
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const CheckResult r = roundtrip(*twin, seed);
        EXPECT_EQ(r.verdict, Verdict::Fail) << "seed " << seed;
        EXPECT_EQ(figure(r, "inverse_edge_most_in_a_chunk"), figure(r, "inverse_edge_chunk_bound")) << seed;
        EXPECT_GT(figure(r, "failures"), 100'000.0) << "seed " << seed;
        EXPECT_NE(r.message.find("reached its bound"), std::string::npos) << r.message;
    }
}

}  // namespace
}  // namespace warpcheck
