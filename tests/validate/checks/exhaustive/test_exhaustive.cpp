// Exhaustive float histograms: every published figure of the 32-bit [0,1)
// samplers, asserted exactly from full 2^32 sweeps; thread independence; the
// non-monotone recounts; and the checks built on the sweep.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "sampling/hash.h"
#include "sampling/interval.h"
#include "sampling/unit_float.h"
#include "support/builtin_case.h"
#include "support/check_harness.h"
#include "validate/checks/checks.h"
#include "validate/api/exhaustive_sweep.h"
#include "validate/api/registry.h"
#include "validate/run/thread_pool.h"

namespace warpcheck {
namespace {

constexpr uint64_t kAll32 = uint64_t{1} << 32;

SweepSummary sweep(const FloatBlockFn& f, uint64_t count, float a, float b, unsigned threads = 2) {
    ThreadPool pool(threads);
    return exhaustive_sweep(f, count, a, b, [&pool](std::size_t n, const std::function<void(std::size_t)>& body) {
        pool.parallel_for(n, body);
    });
}

// Full sweeps are shared between tests: each costs ~0.5 s.
const SweepSummary& mul_sweep() {
    static const SweepSummary s =
        sweep(u32_block_fn([](uint32_t u) { return UnitFloatMul{}.sample(u); }), kAll32, 0.0f, 1.0f);
    return s;
}

TEST(ExhaustiveSweep, MulBy2ToMinus32HasThePublishedFigures) {
    const SweepSummary& s = mul_sweep();
    EXPECT_EQ(s.inputs, kAll32);
    EXPECT_EQ(s.floats_in_interval, 1'065'353'216u);  // floats of [0,1)
    EXPECT_EQ(s.distinct, 83'886'081u);               // 1.0 included
    EXPECT_NEAR(100.0 * static_cast<double>(s.distinct) / static_cast<double>(s.floats_in_interval), 7.87, 0.005);
    EXPECT_EQ(s.distinct_inside, 83'886'080u);
    EXPECT_EQ(s.never_produced, 1'065'353'216u - 83'886'080u);
    // The 128 largest inputs round to 1.0, the only output outside [0,1).
    EXPECT_EQ(s.outside_distinct, 1u);
    EXPECT_EQ(s.outside_inputs, 128u);
    ASSERT_EQ(s.outside_values.size(), 1u);
    EXPECT_EQ(s.outside_values[0].value, 1.0f);
    EXPECT_EQ(s.outside_inputs_of(1.0f), 128u);
    EXPECT_EQ(s.non_monotone_steps, 0u);
    EXPECT_FALSE(s.exact_fallback);
    // [0.5,1): 257 and 255 alternately (ties to even), ideal 256; its first
    // float, 0.5, also takes half a spacing of the binade below: 64 + 1 + 128.
    const BinadeCount* top = s.binade(1, -1);
    ASSERT_NE(top, nullptr);
    EXPECT_EQ(top->ideal, 256.0);
    EXPECT_EQ(top->floats, 1u << 23);
    EXPECT_EQ(top->distinct, 1u << 23);
    EXPECT_EQ(top->min_even, 257u);
    EXPECT_EQ(top->max_even, 257u);
    EXPECT_EQ(top->min_odd, 255u);
    EXPECT_EQ(top->max_odd, 255u);
    EXPECT_EQ(top->edge_multiplicity, 193u);
    EXPECT_EQ(top->pattern(), "257/255");
    // [2^-8, 2^-7): 3 and 1 alternately, ideal 2.
    const BinadeCount* low = s.binade(1, -8);
    ASSERT_NE(low, nullptr);
    EXPECT_EQ(low->ideal, 2.0);
    EXPECT_EQ(low->pattern(), "3/1");
    EXPECT_EQ(low->min_odd, 1u);
    EXPECT_EQ(low->max_even, 3u);
    // [2^-9, 2^-8): exact (u < 2^24), each float once; below, never-produced floats.
    EXPECT_EQ(s.binade(1, -9)->pattern(), "1");
    EXPECT_EQ(s.binade(1, -10)->min_multiplicity, 0u);
    EXPECT_EQ(s.binade(1, -10)->distinct, 1u << 22);
    EXPECT_GT(s.tv_distance, 0.0);
    EXPECT_LT(s.tv_distance, 0.01);
}

TEST(ExhaustiveSweep, LargestFloatBelowOneIsHit255TimesAnd1Point0128Times) {
    // Against [0, 0x1.fffffep-1) the largest float below 1 becomes an outside
    // value too, so its exact count is reported.
    const SweepSummary s =
        sweep(u32_block_fn([](uint32_t u) { return UnitFloatMul{}.sample(u); }), kAll32, 0.0f, kOneMinusEpsilon);
    EXPECT_EQ(s.outside_inputs_of(kOneMinusEpsilon), 255u);
    EXPECT_EQ(s.outside_inputs_of(1.0f), 128u);
}

TEST(ExhaustiveSweep, ClampLeavesTheLargestFloatBelowOneHit383Times) {
    const SweepSummary in01 =
        sweep(u32_block_fn([](uint32_t u) { return UnitFloatMulClamped{}.sample(u); }), kAll32, 0.0f, 1.0f);
    EXPECT_EQ(in01.outside_inputs, 0u);  // never 1.0
    EXPECT_EQ(in01.distinct, 83'886'080u);
    EXPECT_EQ(in01.binade(1, -1)->max_multiplicity, 383u);
    EXPECT_EQ(in01.binade(1, -1)->pattern(), "");  // the alternation is broken by the clamped float
    const SweepSummary below =
        sweep(u32_block_fn([](uint32_t u) { return UnitFloatMulClamped{}.sample(u); }), kAll32, 0.0f, kOneMinusEpsilon);
    EXPECT_EQ(below.outside_distinct, 1u);
    EXPECT_EQ(below.outside_inputs_of(kOneMinusEpsilon), 383u);
}

TEST(ExhaustiveSweep, TwentyFourBitsHit16777216ValuesExactly256TimesEach) {
    const SweepSummary s =
        sweep(u32_block_fn([](uint32_t u) { return UnitFloat24Bit{}.sample(u); }), kAll32, 0.0f, 1.0f);
    EXPECT_EQ(s.distinct, 16'777'216u);
    EXPECT_EQ(s.outside_inputs, 0u);
    EXPECT_EQ(s.non_monotone_steps, 0u);
    uint64_t produced = 0;
    for (const BinadeCount& b : s.binades) {
        if (b.distinct == 0) continue;
        produced += b.distinct;
        EXPECT_EQ(b.inputs, 256u * b.distinct) << "binade " << b.exponent;
        for (uint64_t m : {b.max_even, b.max_odd, b.edge_multiplicity})
            EXPECT_TRUE(m == 0 || m == 256) << "binade " << b.exponent << ": " << m;
        for (uint64_t m : {b.min_even, b.min_odd}) EXPECT_TRUE(m == 0 || m == 256) << "binade " << b.exponent;
    }
    EXPECT_EQ(produced, 16'777'216u);
    EXPECT_EQ(s.binade(1, -1)->pattern(), "256");  // [0.5,1): the only binade with every float
}

TEST(ExhaustiveSweep, CountsDoNotDependOnTheThreadCount) {
    const SweepSummary& two = mul_sweep();
    const SweepSummary one =
        sweep(u32_block_fn([](uint32_t u) { return UnitFloatMul{}.sample(u); }), kAll32, 0.0f, 1.0f, 1);
    EXPECT_EQ(one.distinct, two.distinct);
    EXPECT_EQ(one.outside_inputs, two.outside_inputs);
    EXPECT_EQ(one.never_produced, two.never_produced);
    EXPECT_EQ(one.tv_distance, two.tv_distance);  // computed from integer counts: bit for bit
    ASSERT_EQ(one.binades.size(), two.binades.size());
    for (std::size_t k = 0; k < one.binades.size(); ++k) {
        const BinadeCount &x = one.binades[k], &y = two.binades[k];
        EXPECT_EQ(x.distinct, y.distinct);
        EXPECT_EQ(x.inputs, y.inputs);
        EXPECT_EQ(x.min_multiplicity, y.min_multiplicity);
        EXPECT_EQ(x.max_multiplicity, y.max_multiplicity);
        EXPECT_EQ(x.abs_deviation, y.abs_deviation);
    }
}

// Non-monotone functions on the 2^-24 grid, with a direct count to compare:
// over all of [0,1), and within [0.5,1) (one binade: one histogram window).
float scrambled(uint64_t i) { return static_cast<float>(static_cast<uint32_t>(mix64(i) >> 40)) * 0x1p-24f; }
float scrambled_top(uint64_t i) {
    return static_cast<float>((uint32_t{1} << 23) | static_cast<uint32_t>(mix64(i) >> 41)) * 0x1p-24f;
}

template <float (*F)(uint64_t)>
void expect_matches_direct_count(uint64_t count, unsigned threads) {
    std::vector<uint32_t> hist(uint64_t{1} << 24, 0);
    for (uint64_t i = 0; i < count; ++i) ++hist[static_cast<uint32_t>(F(i) * 0x1p24f)];
    uint64_t distinct = 0, top_min = ~uint64_t{0}, top_max = 0;
    for (std::size_t k = 0; k < hist.size(); ++k) {
        distinct += hist[k] > 0;
        if (k >= (std::size_t{1} << 23)) {  // [0.5, 1)
            top_min = std::min<uint64_t>(top_min, hist[k]);
            top_max = std::max<uint64_t>(top_max, hist[k]);
        }
    }
    const SweepSummary s = sweep(
        [](uint64_t first, std::size_t n, float* out) {
            for (std::size_t i = 0; i < n; ++i) out[i] = F(first + i);
        },
        count, 0.0f, 1.0f, threads);
    EXPECT_TRUE(s.exact_fallback);
    EXPECT_GT(s.non_monotone_steps, count / 4);
    EXPECT_EQ(s.distinct, distinct);
    EXPECT_EQ(s.binade(1, -1)->min_multiplicity, top_min);
    EXPECT_EQ(s.binade(1, -1)->max_multiplicity, top_max);
}

TEST(ExhaustiveSweep, NonMonotoneFunctionsAreRecountedExactlyBySorting) {
    expect_matches_direct_count<scrambled>(3u << 22, 2);
}

TEST(ExhaustiveSweep, NonMonotoneFunctionsAreRecountedExactlyByHistogramWindows) {
    expect_matches_direct_count<scrambled_top>((uint64_t{1} << 26) + 12345, 2);  // above the sort limit
}

// The window recount (radix-partitioned counting within the memory bound),
// reached on a reduced range by lowering the limits: three binades a window and
// seven (further windows after too many outputs outside the first), twenty (the
// few outputs outside the first window counted by sorting), against the
// recount by sorting every output, field by field; and outputs produced
// thousands of times each (one-byte counters that wrap).
void expect_same_recount(const SweepSummary& x, const SweepSummary& y) {
    EXPECT_EQ(x.distinct, y.distinct);
    EXPECT_EQ(x.never_produced, y.never_produced);
    EXPECT_EQ(x.outside_inputs, y.outside_inputs);
    EXPECT_EQ(x.tv_distance, y.tv_distance);
    EXPECT_EQ(x.lowest_inside, y.lowest_inside);
    ASSERT_EQ(x.binades.size(), y.binades.size());
    for (std::size_t k = 0; k < x.binades.size(); ++k) {
        const BinadeCount &a = x.binades[k], &b = y.binades[k];
        EXPECT_EQ(a.distinct, b.distinct) << k;
        EXPECT_EQ(a.inputs, b.inputs) << k;
        EXPECT_EQ(a.min_multiplicity, b.min_multiplicity) << k;
        EXPECT_EQ(a.max_multiplicity, b.max_multiplicity) << k;
        EXPECT_EQ(a.most_produced, b.most_produced) << k;
        EXPECT_EQ(a.abs_deviation, b.abs_deviation) << k;
    }
}

TEST(ExhaustiveSweep, WindowRecountWithinItsMemoryBoundMatchesSorting) {
    const FloatBlockFn f = [](uint64_t first, std::size_t n, float* out) {
        for (std::size_t i = 0; i < n; ++i) out[i] = scrambled(first + i);
    };
    const uint64_t count = (uint64_t{1} << 22) + 777;  // a full chunk and a partial one
    ThreadPool pool(2);
    const ParallelFor parallel = [&pool](std::size_t n, const std::function<void(std::size_t)>& body) {
        pool.parallel_for(n, body);
    };
    const SweepSummary sorted = exhaustive_sweep(f, count, 0.0f, 1.0f, parallel, {.sort_limit = count});
    ASSERT_TRUE(sorted.exact_fallback);
    EXPECT_GT(sorted.binades.size(), 5u);
    for (const int window : {3, 7, 20}) {
        SCOPED_TRACE(window);
        expect_same_recount(exhaustive_sweep(f, count, 0.0f, 1.0f, parallel, {.sort_limit = 0, .window_binades = window}),
                            sorted);
    }
    const FloatBlockFn coarse = [](uint64_t first, std::size_t n, float* out) {
        for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(mix64(first + i) >> 54) * 0x1p-10f;
    };
    const SweepSummary coarse_sorted = exhaustive_sweep(coarse, count, 0.0f, 1.0f, parallel, {.sort_limit = count});
    ASSERT_TRUE(coarse_sorted.exact_fallback);
    EXPECT_GT(coarse_sorted.binade(1, -1)->most_multiplicity, 3000u);  // 1024 outputs, ~4096 times each
    for (const int window : {2, 64}) {
        SCOPED_TRACE(window);
        expect_same_recount(
            exhaustive_sweep(coarse, count, 0.0f, 1.0f, parallel, {.sort_limit = 0, .window_binades = window}),
            coarse_sorted);
    }
}

// A sampler monotone but for swapped neighbours (i ^ 1) on a grid of 2^24
// inputs (four chunks): with a window of nine binades, the 2^15 outputs below it
// all come from the first chunk. The strays' budget is shared by the chunks
// (2^16 keys here), so they are counted by sorting in the window's own pass;
// a budget of 2^14 per chunk sent this through a second run of f. With three
// binades (2^21 outputs outside) the budget overruns and further windows
// count the rest. Both against the recount by sorting, field by field.
TEST(ExhaustiveSweep, LocallySwappedSamplerIsRecountedInOnePass) {
    const FloatBlockFn f = [](uint64_t first, std::size_t n, float* out) {
        for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>((first + i) ^ 1u) * 0x1p-24f;
    };
    const uint64_t count = uint64_t{1} << 24;
    ThreadPool pool(2);
    const ParallelFor parallel = [&pool](std::size_t n, const std::function<void(std::size_t)>& body) {
        pool.parallel_for(n, body);
    };
    const SweepSummary sorted = exhaustive_sweep(f, count, 0.0f, 1.0f, parallel, {.sort_limit = count});
    ASSERT_TRUE(sorted.exact_fallback);
    EXPECT_EQ(sorted.recount_passes, 1);
    EXPECT_EQ(sorted.non_monotone_steps, count / 2);
    const SweepSummary nine = exhaustive_sweep(f, count, 0.0f, 1.0f, parallel, {.sort_limit = 0, .window_binades = 9});
    EXPECT_EQ(nine.recount_passes, 1);
    EXPECT_EQ(nine.non_monotone_steps, count / 2);  // counted in the window pass, chunk borders included
    expect_same_recount(nine, sorted);
    const SweepSummary three = exhaustive_sweep(f, count, 0.0f, 1.0f, parallel, {.sort_limit = 0, .window_binades = 3});
    EXPECT_GT(three.recount_passes, 1);
    EXPECT_EQ(three.non_monotone_steps, count / 2);
    expect_same_recount(three, sorted);
}

TEST(ExhaustiveSweep, NegativeAndZeroSpanningIntervals) {
    // t on the 2^-24 grid mapped to [-1, 1): x = 2t - 1 exactly, each value once.
    const SweepSummary s = sweep(
        [](uint64_t first, std::size_t n, float* out) {
            for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(first + i) * 0x1p-23f - 1.0f;
        },
        uint64_t{1} << 24, -1.0f, 1.0f);
    EXPECT_EQ(s.distinct, uint64_t{1} << 24);
    EXPECT_EQ(s.outside_inputs, 0u);
    EXPECT_EQ(s.non_monotone_steps, 0u);
    // Negative binades hold magnitudes (2^e, 2^(e+1)]: -1 is the edge of e = -1.
    const BinadeCount* neg = s.binade(-1, -1);
    ASSERT_NE(neg, nullptr);
    EXPECT_EQ(neg->first, -1.0f);
    EXPECT_EQ(neg->edge_multiplicity, 1u);
    EXPECT_EQ(neg->ideal, 0.5);  // spacing 2^-24 against 2 / 2^24 per input
    EXPECT_EQ(s.floats_in_interval, 2u * 1'065'353'216u);  // (0, 1] mirrored, and [0, 1)
}

TEST(ExhaustiveSweep, RejectsBadArguments) {
    const FloatBlockFn f = [](uint64_t, std::size_t n, float* out) { std::fill(out, out + n, 0.0f); };
    ParallelFor serial = [](std::size_t n, const std::function<void(std::size_t)>& body) {
        for (std::size_t i = 0; i < n; ++i) body(i);
    };
    EXPECT_THROW(exhaustive_sweep(f, 0, 0.0f, 1.0f, serial), std::invalid_argument);
    EXPECT_THROW(exhaustive_sweep(f, kAll32 + 1, 0.0f, 1.0f, serial), std::invalid_argument);
    EXPECT_THROW(exhaustive_sweep(f, 16, 1.0f, 1.0f, serial), std::invalid_argument);
    EXPECT_THROW(exhaustive_sweep(f, 16, std::nanf(""), 1.0f, serial), std::invalid_argument);
}

TEST(ExhaustiveSweep, NaNOutputsAreOutsideAndCounted) {
    const SweepSummary s = sweep(
        [](uint64_t first, std::size_t n, float* out) {
            for (std::size_t i = 0; i < n; ++i)
                out[i] = (first + i) % 1000 == 999 ? std::nanf("") : static_cast<float>(first + i) * 0x1p-20f;
        },
        uint64_t{1} << 20, 0.0f, 1.0f);
    EXPECT_EQ(s.outside_inputs, (uint64_t{1} << 20) / 1000);
    EXPECT_GT(s.non_monotone_steps, 0u);
}

TEST(ExhaustiveSweep, LerpsOnTheirTGrid) {
    auto lerp_fn = [](LerpInterval lerp) {
        return [lerp](uint64_t first, std::size_t n, float* out) {
            for (std::size_t i = 0; i < n; ++i) out[i] = lerp.sample(static_cast<float>(first + i) * 0x1p-24f);
        };
    };
    const uint64_t grid = uint64_t{1} << 24;
    const SweepSummary offset = sweep(lerp_fn(LerpInterval(100.0f, 101.0f, LerpInterval::Form::Offset)), grid, 100.0f, 101.0f);
    EXPECT_EQ(offset.outside_inputs_of(101.0f), 64u);  // t >= 1 - 2^-18 rounds to b
    EXPECT_EQ(offset.non_monotone_steps, 0u);
    const SweepSummary blend = sweep(lerp_fn(LerpInterval(1.0f, 3.0f, LerpInterval::Form::Blend)), grid, 1.0f, 3.0f);
    EXPECT_EQ(blend.outside_inputs_of(3.0f), 0u);
    EXPECT_EQ(blend.non_monotone_steps, 1'398'101u);
    const SweepSummary offset13 = sweep(lerp_fn(LerpInterval(1.0f, 3.0f, LerpInterval::Form::Offset)), grid, 1.0f, 3.0f);
    EXPECT_EQ(offset13.outside_inputs_of(3.0f), 1u);
    EXPECT_EQ(offset13.non_monotone_steps, 0u);
}

// --- the checks --------------------------------------------------------------

using testing::builtin_case;

TEST(ExhaustiveCheck, FailsTheMultiplyForReaching1AndStatesTheRule) {
    const CheckResult r = testing::run_check(*make_exhaustive_check(), builtin_case("unit_float_mul32"));
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_EQ(*r.figure("distinct"), 83'886'081.0);
    EXPECT_EQ(*r.figure("outside_inputs"), 128.0);
    EXPECT_EQ(*r.figure("binade_-1_max"), 257.0);
    EXPECT_NE(r.summary.find("83886081 distinct, 128 inputs -> 1"), std::string::npos) << r.summary;
    EXPECT_NE(r.message.find("half-open"), std::string::npos) << r.message;
    ASSERT_FALSE(r.plots.empty());
    EXPECT_TRUE(r.plots[0].log_y);
    ASSERT_FALSE(r.tables.empty());
}

TEST(ExhaustiveCheck, PassesTheClampedMultiplyWithItsBiasReported) {
    const CheckResult r = testing::run_check(*make_exhaustive_check(), builtin_case("unit_float_mul32_clamped"));
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
    EXPECT_EQ(*r.figure("binade_-1_max"), 383.0);
    EXPECT_EQ(*r.figure("outside_inputs"), 0.0);
    EXPECT_GT(*r.figure("tv_distance"), 0.0);
    // The worst binade relative to its ideal: [2^-8, 2^-7), 3 and 1 against 2.
    EXPECT_EQ(*r.figure("max_relative_deviation"), 0.5);
}

TEST(ExhaustiveCheck, FailsALerpThatReachesB) {
    const CheckResult r = testing::run_check(*make_exhaustive_check(), builtin_case("lerp_offset[a=100,b=101]"));
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_EQ(*r.figure("inputs_to_b"), 64.0);
}

TEST(BinadeCheck, SixtyFourBitSamplersPass) {
    for (const char* name : {"unit_float_walker", "unit_float_reynolds",
                             "uniform_float_interval[a=-3,b=5]", "uniform_float_interval[a=0.999,b=1.001]"}) {
        const CheckResult r = testing::run_check(*make_binade_check(), builtin_case(name));
        EXPECT_EQ(r.verdict, Verdict::Pass) << name << ": " << r.summary;
        EXPECT_GE(*r.figure("samples"), 16'777'216.0);
    }
}

TEST(BinadeCheck, SeesThe257Over255AlternationOfThe32BitMultiply) {
    WarpCaseInfo info;
    info.family = "mul32_as_64";
    info.description = "the clamped 2^-32 multiply fed 64 bits";
    info.domain = chi2::Domain::interval(0.0, 1.0);
    auto warp = make_warp_case(
        info, warp_of([](uint64_t bits) { return UnitFloatMulClamped{}.sample(static_cast<uint32_t>(bits >> 32)); })
                  .with_pdf([](float) { return 1.0f; })
                  .with_invert([](float x) { return uint64_t{UnitFloatMul{}.invert(x)} << 32; }));
    const CheckResult r = testing::run_check(*make_binade_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail) << r.summary;
    EXPECT_LT(*r.figure("parity_p_value"), 1e-12);
}

TEST(ExhaustiveRoundtripCheck, RunsOnlyWhenAskedAndReportsTheWobbleOfALerp) {
    RunOptions options;
    EXPECT_FALSE(make_exhaustive_roundtrip_check()->runs_by_default(options));
    options.exhaustive = true;
    EXPECT_TRUE(make_exhaustive_roundtrip_check()->runs_by_default(options));
#if defined(__SANITIZE_ADDRESS__)
    // 2^30 floats through the warp take many minutes under AddressSanitizer;
    // the release test build runs this sweep (the sweep engine is covered here
    // by the exhaustive tests of the 32-bit samplers).
    GTEST_SKIP() << "full sweep of every float in [0,1): run in the release test build";
#endif
    // Its steps down are rounding wobble within the stated tolerance (issue 12):
    // reported, not failed (test_exhaustive_verdicts.cpp has the failing twin).
    // (Built here: being no flaw, lerp_blend[a=1,b=3] left the flawed catalogue in issue 22.)
    const auto lerp = make_warp_case(
        {.family = "lerp_blend", .domain = chi2::Domain::interval(1, 3)},
        LerpInterval(1.0f, 3.0f, LerpInterval::Form::Blend));
    const CheckResult r = testing::run_check(*make_exhaustive_roundtrip_check(), *lerp);
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
    EXPECT_EQ(*r.figure("inputs"), 1'065'353'216.0);
    EXPECT_GT(*r.figure("steps_down"), 0.0);
    EXPECT_EQ(*r.figure("roundtrip_failures"), 0.0);
    EXPECT_EQ(*r.figure("bad_pdf"), 0.0);
}

}  // namespace
}  // namespace warpcheck
