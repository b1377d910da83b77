// The sweep engine's code paths give the same summary, field by field: the
// AVX-512 run scan (where the CPU has it) against the portable one, and both
// against the simplest count the engine has, the recount by sorting every
// output (reached by sweeping the same function backwards, which makes it
// non-monotone without changing how often each output comes). The functions
// cover long and short runs, runs across chunk borders, -0 beside +0, NaNs with
// different payloads, outputs outside [a,b), negative binades and a partial
// last chunk.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <optional>
#include <string>

#include "sampling/hash.h"
#include "validate/api/exhaustive_sweep.h"
#include "validate/run/thread_pool.h"

namespace warpcheck {
namespace {

using chi2::SweepLimits;

// Bits, so that NaNs and -0 compare as what they are.
uint32_t bits(float x) { return std::bit_cast<uint32_t>(x); }

void expect_same_counts(const SweepSummary& x, const SweepSummary& y) {
    EXPECT_EQ(x.inputs, y.inputs);
    EXPECT_EQ(x.distinct, y.distinct);
    EXPECT_EQ(x.distinct_inside, y.distinct_inside);
    EXPECT_EQ(x.outside_distinct, y.outside_distinct);
    EXPECT_EQ(x.outside_inputs, y.outside_inputs);
    EXPECT_EQ(x.floats_in_interval, y.floats_in_interval);
    EXPECT_EQ(x.never_produced, y.never_produced);
    EXPECT_EQ(x.tv_distance, y.tv_distance);
    EXPECT_EQ(bits(x.lowest_inside), bits(y.lowest_inside));
    EXPECT_EQ(bits(x.highest_inside), bits(y.highest_inside));
    ASSERT_EQ(x.outside_values.size(), y.outside_values.size());
    for (std::size_t k = 0; k < x.outside_values.size(); ++k) {
        EXPECT_EQ(bits(x.outside_values[k].value), bits(y.outside_values[k].value)) << k;
        EXPECT_EQ(x.outside_values[k].inputs, y.outside_values[k].inputs) << k;
    }
    ASSERT_EQ(x.binades.size(), y.binades.size());
    for (std::size_t k = 0; k < x.binades.size(); ++k) {
        SCOPED_TRACE("binade " + std::to_string(k));
        const BinadeCount &a = x.binades[k], &b = y.binades[k];
        EXPECT_EQ(a.sign, b.sign);
        EXPECT_EQ(a.exponent, b.exponent);
        EXPECT_EQ(bits(a.first), bits(b.first));
        EXPECT_EQ(bits(a.last), bits(b.last));
        EXPECT_EQ(a.floats, b.floats);
        EXPECT_EQ(a.distinct, b.distinct);
        EXPECT_EQ(a.inputs, b.inputs);
        EXPECT_EQ(a.ideal, b.ideal);
        EXPECT_EQ(a.min_multiplicity, b.min_multiplicity);
        EXPECT_EQ(a.max_multiplicity, b.max_multiplicity);
        EXPECT_EQ(a.edge_multiplicity, b.edge_multiplicity);
        EXPECT_EQ(bits(a.most_produced), bits(b.most_produced));
        EXPECT_EQ(bits(a.least_produced), bits(b.least_produced));
        EXPECT_EQ(a.most_multiplicity, b.most_multiplicity);
        EXPECT_EQ(a.least_multiplicity, b.least_multiplicity);
        EXPECT_EQ(a.min_even, b.min_even);
        EXPECT_EQ(a.max_even, b.max_even);
        EXPECT_EQ(a.min_odd, b.min_odd);
        EXPECT_EQ(a.max_odd, b.max_odd);
        EXPECT_EQ(a.abs_deviation, b.abs_deviation);
        EXPECT_EQ(a.pattern(), b.pattern());
    }
}

void expect_same_summary(const SweepSummary& x, const SweepSummary& y) {
    expect_same_counts(x, y);
    EXPECT_EQ(x.non_monotone_steps, y.non_monotone_steps);
    EXPECT_EQ(x.exact_fallback, y.exact_fallback);
}

struct Case {
    std::string name;
    std::function<float(uint64_t)> f;
    uint64_t count;
    float a, b;
};

// Two full chunks (2^22 inputs each) and a partial one.
constexpr uint64_t kCount = 2 * (uint64_t{1} << 22) + 777;

std::vector<Case> monotone_cases() {
    return {
        // Runs from one to thousands long, every binade of [0,1) below the top.
        {"sqrt", [](uint64_t i) { return std::sqrt(static_cast<float>(i) * 0x1p-24f); }, kCount, 0.0f, 1.0f},
        // u * 2^-32 on a grid: runs of 1 to 256 and the binade edges' share.
        {"mul_grid", [](uint64_t i) { return static_cast<float>(static_cast<uint32_t>(i << 8)) * 0x1p-32f; }, kCount,
         0.0f, 1.0f},
        // A narrow interval: most outputs outside it, on both sides.
        {"narrow", [](uint64_t i) { return static_cast<float>(i) * 0x1p-20f; }, kCount, 3.0f, 3.5f},
        // A run longer than a chunk: 0.875 from input 3 * 2^20 on.
        {"clamp", [](uint64_t i) { return std::min(static_cast<float>(i) * 0x1p-22f, 0.75f) + 0.125f; }, kCount, 0.0f,
         1.0f},
        // Negative binades, zero and positive ones; -0 and +0 alternate in the
        // run of zeros (one key, several bit patterns).
        {"signed_zero",
         [](uint64_t i) {
             const float x = static_cast<float>(static_cast<int64_t>(i / 7) - 900000) * 0x1p-20f;
             return x == 0.0f && (i & 1) ? -0.0f : x;
         },
         kCount, -1.0f, 1.0f},
        // Denormals around zero.
        {"denormal",
         [](uint64_t i) {
             const float x = static_cast<float>(static_cast<int64_t>(i / 3) - 1000) * 0x1p-130f;
             return x == 0.0f && i % 3 == 1 ? -0.0f : x;
         },
         6000, -1e-30f, 1e-30f},
        // NaNs with four payloads at the end (one key above +inf).
        {"nan_tail",
         [](uint64_t i) {
             if (i > 5000000) return std::bit_cast<float>(0x7fc00000u | static_cast<uint32_t>(i & 3));
             return static_cast<float>(i) * 0x1p-23f;
         },
         5100000, 0.0f, 0.5f},
        // Equal multiplicities everywhere (ties for the most and least produced).
        {"steps", [](uint64_t i) { return static_cast<float>(i / 4096) * 0x1p-10f; }, kCount, 0.0f, 8.0f},
        // One output.
        {"constant", [](uint64_t) { return 0.3f; }, kCount, 0.0f, 1.0f},
        // Fewer inputs than a vector.
        {"short", [](uint64_t i) { return static_cast<float>(i) * 0.01f; }, 37, 0.0f, 1.0f},
    };
}

class SweepEnginePaths : public ::testing::Test {
protected:
    SweepSummary run(const std::function<float(uint64_t)>& f, uint64_t count, float a, float b, bool backwards,
                     const SweepLimits& limits) {
        const FloatBlockFn block = [&f, count, backwards](uint64_t first, std::size_t n, float* out) {
            for (std::size_t i = 0; i < n; ++i) out[i] = f(backwards ? count - 1 - (first + i) : first + i);
        };
        return exhaustive_sweep(block, count, a, b, parallel_, limits);
    }

    // The same sweep with the sampler fused with the run scan
    // (u32_borders_fn), where the CPU has it; otherwise empty (no sweep).
    std::optional<SweepSummary> run_fused(const std::function<float(uint64_t)>& f, uint64_t count, float a,
                                          float b) {
        const auto sample = [&f](uint32_t u) { return f(u); };
        const FloatBordersFn borders = u32_borders_fn(sample);
        if (!borders) return std::nullopt;
        return exhaustive_sweep(u32_block_fn(sample), borders, count, a, b, parallel_);
    }

    ThreadPool pool_{2};
    ParallelFor parallel_ = [this](std::size_t n, const std::function<void(std::size_t)>& body) {
        pool_.parallel_for(n, body);
    };
};

TEST_F(SweepEnginePaths, RunScanMatchesThePortableScanAndTheSortedRecount) {
    for (const Case& c : monotone_cases()) {
        SCOPED_TRACE(c.name);
        const SweepSummary fast = run(c.f, c.count, c.a, c.b, false, {});
        const SweepSummary portable = run(c.f, c.count, c.a, c.b, false, {.portable = true});
        EXPECT_FALSE(fast.exact_fallback);
        expect_same_summary(fast, portable);
        if (const auto fused = run_fused(c.f, c.count, c.a, c.b)) expect_same_summary(*fused, portable);
        // Backwards: the same outputs as often, counted by sorting them all.
        const SweepSummary sorted = run(c.f, c.count, c.a, c.b, true, {});
        EXPECT_EQ(sorted.exact_fallback, c.name != "constant");
        expect_same_counts(fast, sorted);
    }
}

TEST_F(SweepEnginePaths, NonMonotoneStepsAreCountedAlikeOnBothScans) {
    const auto scrambled = [](uint64_t i) {
        return static_cast<float>(static_cast<uint32_t>(mix64(i) >> 40)) * 0x1p-24f;
    };
    const SweepSummary fast = run(scrambled, kCount, 0.0f, 1.0f, false, {});
    const SweepSummary portable = run(scrambled, kCount, 0.0f, 1.0f, false, {.portable = true});
    EXPECT_TRUE(fast.exact_fallback);
    expect_same_summary(fast, portable);
    if (const auto fused = run_fused(scrambled, kCount, 0.0f, 1.0f)) expect_same_summary(*fused, portable);
}

// The fused scan must find every border, wherever it falls: at each position
// of a group of 64 (and of the padded tail), a monotone step, whose runs the
// fused scan counts itself (checked against the portable scan, field by
// field), and one output above its neighbours, a step up and down.
TEST_F(SweepEnginePaths, FusedScanFindsABorderAtEveryLaneOfAGroup) {
    const auto sample = [](uint32_t) { return 0.0f; };
    if (!u32_borders_fn(sample)) GTEST_SKIP() << "no AVX-512 on this CPU: the fused scan is not used";
    for (uint64_t at = 0; at < 200; ++at) {
        SCOPED_TRACE(at);
        // 0.25 before input `at`, 0.5 from it on: two runs of lengths at and 197 - at.
        const auto step = [at](uint64_t i) { return i >= at ? 0.5f : 0.25f; };
        const auto fused_step = run_fused(step, 197, 0.0f, 1.0f);
        ASSERT_TRUE(fused_step.has_value());
        const SweepSummary portable_step = run(step, 197, 0.0f, 1.0f, false, {.portable = true});
        expect_same_summary(*fused_step, portable_step);
        EXPECT_FALSE(fused_step->exact_fallback);
        const BinadeCount* half = fused_step->binade(1, -1);
        ASSERT_NE(half, nullptr);
        EXPECT_EQ(half->edge_multiplicity, at < 197 ? 197 - at : 0u);  // 0.5 is the binade's first float
        const BinadeCount* quarter = fused_step->binade(1, -2);
        ASSERT_NE(quarter, nullptr);
        EXPECT_EQ(quarter->edge_multiplicity, std::min<uint64_t>(at, 197));  // and 0.25 of its own
        // 0.25 everywhere but 0.5 at input `at` (none from 197 on).
        const auto f = [at](uint64_t i) { return i == at ? 0.5f : 0.25f; };
        const auto fused = run_fused(f, 197, 0.0f, 1.0f);
        ASSERT_TRUE(fused.has_value());
        const SweepSummary portable = run(f, 197, 0.0f, 1.0f, false, {.portable = true});
        expect_same_summary(*fused, portable);
        EXPECT_EQ(fused->outside_distinct + fused->distinct_inside, at < 197 ? 2u : 1u);
        EXPECT_EQ(fused->non_monotone_steps, at < 196 ? 1u : 0u);  // 0.5 -> 0.25 after it
    }
}

}  // namespace
}  // namespace warpcheck
